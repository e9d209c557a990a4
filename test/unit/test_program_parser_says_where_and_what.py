"""The program format of docs/programs.md: every statement reads as documented (numbers, variables
and arithmetic wherever a number goes, options in any order, comments, blank lines, nested
loops, the file's own line numbers), and every mistake is refused with its line, its column and
what was expected there. The example programs shipped in config/programs/ all read."""
from pathlib import Path

import pytest

from jaka_driver.programs import ProgramError, parse
from jaka_driver.programs.language import (Arithmetic, CircularMove, JointMove, LinearMove,
                                           Negated, Number, Repeat, SetOutput, SetVariable,
                                           Variable, Wait, WaitInput, WaitUntil)

PROGRAMS = Path(__file__).resolve().parents[2] / "config" / "programs"


def test_every_statement_reads_as_documented():
    program = parse("""\
# a comment line, then a blank one

var 3 count = -2.5   # trailing comment
joint_move [0, 1.5, -1.5, 1.5, 1.5, 0] accel 2 speed 1
linear_move [1, 2, 3, 0, 0, 0.1] speed count * (2 + 1)
circular_move mid [1, 2, 3, 0, 0, 0] end [4, 5, 6, 0, 0, 0] turns 1.5 mode 2 speed 50 accel 1e3
set_output analog extension 1 = -count / 2
wait 0.25
wait_input digital tool 0 >= 1 timeout 3
wait_until count != 0
set count = count - 1
repeat 2
  repeat forever
    wait 1
  end
end
""", "demo")
    s = program.statements
    assert [type(x) for x in s] == [JointMove, LinearMove, CircularMove, SetOutput, Wait,
                                     WaitInput, WaitUntil, SetVariable, Repeat]
    assert [x.line for x in s] == [4, 5, 6, 7, 8, 9, 10, 11, 12]
    assert program.variables[0].id == 3 and program.variables[0].value == -2.5
    count = Variable(3, "count")
    assert s[0].speed == Number(1.0) and s[0].accel == Number(2.0)
    assert s[0].joints[2] == Negated(Number(1.5))
    assert s[1].speed == Arithmetic("*", count, Arithmetic("+", Number(2.0), Number(1.0)))
    assert s[1].accel == Number(0.0)                                  # the default
    assert (s[2].turns, s[2].mode, s[2].accel) == (Number(1.5), Number(2.0), Number(1000.0))
    assert (s[3].signal, s[3].io_type, s[3].index) == ("analog", 2, 1)
    assert (s[5].signal, s[5].io_type, s[5].op, s[5].timeout) == ("digital", 1, ">=",
                                                                    Number(3.0))
    assert s[6].timeout is None and s[6].variable == count
    outer = s[8]
    assert outer.count == Number(2.0) and outer.body[0].count is None
    assert outer.body[0].line == 13 and outer.body[0].body[0].line == 14
    values = {3: -2.5}
    assert s[1].speed.evaluate(values) == -7.5


@pytest.mark.parametrize("text, line, column, message", [
    ("joint_move [0, 0, 0, 0, 0, 0] speed fast\n", 1, 1 + len("joint_move [0, 0, 0, 0, 0, 0] speed "),
     "'fast' is not a declared variable"),
    ("\n\nlinear_move [1, 2, 3] speed 10\n", 3, len("linear_move [1, 2, 3") + 1,
     "the pose (mm, rotation vector rad) has 3 values, expected 6"),
    ("joint_move [0, 0, 0, 0, 0, 0]\n", 1, 30, "expected 'speed' and its value (rad/s), "
     "found end of line"),
    ("joint_move [0, 0, 0, 0, 0, 0] speed 1 speed 2\n", 1, 39, "'speed' is given twice"),
    ("joint_move [0, 0, 0, 0, 0, 0] speed 1 turns 2\n", 1, 39, "expected 'accel', found "
     "'turns'"),
    ("circular_move [1, 2, 3, 0, 0, 0]\n", 1, 15, "expected 'mid' and the middle pose, "
     "found '['"),
    ("set_output digital cabinet 3 1\n", 1, 30, "expected '=' and the value, found '1'"),
    ("set_output digital drawer 3 = 1\n", 1, 20, "expected the IO type (cabinet or tool or "
     "extension), found 'drawer'"),
    ("set_output digital 5 3 = 1\n", 1, 20, "IO type is 5, expected 0–2"),
    ("set_output digital cabinet 2.5 = 1\n", 1, 28, "expected the channel index (from 0) "
     "(a whole number), found '2.5'"),
    ("wait_input digital cabinet 2 = 1\n", 1, 30, "expected a comparison"),
    ("wait 1 2\n", 1, 8, "expected the end of the line (or a # comment), found '2'"),
    ("wait $\n", 1, 6, "unexpected character '$'"),
    ("jump 3\n", 1, 1, "expected a statement (joint_move, linear_move"),
    ("42\n", 1, 1, "expected a statement"),
    ("repeat 2\n  wait 1\n", 1, 1, "the 'repeat' of line 1 has no 'end'"),
    ("wait 1\nend\n", 2, 1, "'end' without a 'repeat' it closes"),
    ("var 0 x = 1\n", 1, 5, "variable id is 0, expected 1–100"),
    ("var 1 x = 1\nvar 1 y = 2\n", 2, 5, "variable id 1 is already declared on line 1"),
    ("var 1 x = 1\nvar 2 x = 2\n", 2, 7, "variable 'x' is already declared"),
    ("var 1 x = y\n", 1, 11, "expected a number (the initial value), found 'y'"),
    ("var 1 repeat = 1\n", 1, 7, "expected the variable's name"),
    ("repeat 2\n  var 1 x = 1\nend\n", 2, 3, "variables are declared outside repeat blocks"),
    ("set y = 1\n", 1, 5, "'y' is not a declared variable (declared: none"),
    ("wait (1 + 2\n", 1, 12, "expected ')', found end of line"),
    ("linear_move [1, 2, 3, 4, 5 6] speed 1\n", 1, 28, "expected ',' or ']' in the pose"),
])
def test_a_mistake_is_refused_with_its_line_column_and_what_was_expected(text, line, column,
                                                                         message):
    with pytest.raises(ProgramError) as refused:
        parse(text, "bad")
    error = refused.value
    assert (error.line, error.column) == (line, column), str(error)
    assert message in error.message
    assert str(error).startswith(f"line {line}, column {column}: ")


def test_the_example_programs_all_read():
    files = sorted(PROGRAMS.glob("*.jdp"))
    assert len(files) >= 2
    for path in files:
        program = parse(path.read_text(), path.stem)
        assert program.statements, path
    three = parse((PROGRAMS / "three_moves.jdp").read_text(), "three_moves")
    moves = [s for s in three.statements if isinstance(s, (JointMove, LinearMove,
                                                            CircularMove))]
    assert len(moves) == 3
