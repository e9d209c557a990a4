"""JAKA's SDK's ten program functions and its circular_move (test/jaka_sdk_model.py: what the SDK
sends and how strictly it reads, from sdk_wire_formats §4 and §9), unmodified, against the
emulator serving programs of the twin's format from a folder: program_load finds a program by
the name with the ".jks" the SDK appends, plays it through its three moves, pauses (the state
reads 2, the line stands), resumes to the program's end pose, aborts (the queue empty); a user
variable the SDK sets is read back and counted by the program; movc runs the twin's arc and
three points on one line are refused."""
from __future__ import annotations

import json
import time

import numpy as np
import pytest

from support.emulated_arm import emulator_with_programs, programs_folder, sdk_logged_in
from support.jaka_sdk_model import ABS, RC_FAILED, RC_OK
from support.ros_harness import wait_until


#: the example's end: its half circle ends here (mm), 50 mm below and 160 mm beside home
THREE_MOVES_END_MM = (642.0, 114.0, 393.0)
LINE_OF_THE_LINE, LINE_OF_THE_ARC = 6, 7            # three_moves.jdp's linear and circular move


@pytest.fixture(scope="module")
def emu(tmp_path_factory):
    with emulator_with_programs(programs_folder(tmp_path_factory.mktemp("programs"))) as emulator:
        yield emulator


@pytest.fixture
def sdk(emu):
    with sdk_logged_in(emu) as handle:
        yield handle


def _state(sdk) -> int:
    rc, state = sdk.get_program_state()
    assert rc == RC_OK
    return state


def _tcp_mm(sdk) -> np.ndarray:
    return np.array(sdk.get_robot_status()[1].cartesiantran_position[:3])


def _comes_to_rest(sdk, timeout: float = 3.0) -> bool:
    """The TCP moves less than 0.05 mm in 0.2 s (the arm holds still), within ``timeout``."""
    def still() -> bool:
        before = _tcp_mm(sdk)
        time.sleep(0.2)
        return np.linalg.norm(_tcp_mm(sdk) - before) < 0.05
    return wait_until(still, timeout)


def test_the_sdk_loads_plays_pauses_resumes_and_follows_a_program(sdk):
    assert sdk.program_load("three_moves") == RC_OK
    assert json.loads(sdk.sent[-1]) == {"cmdName": "load_program",
                                        "programName": "three_moves.jks"}
    assert sdk.get_loaded_program() == (RC_OK, "three_moves.jks")
    assert sdk.program_run() == RC_OK
    assert wait_until(lambda: sdk.get_current_line()[1] >= LINE_OF_THE_LINE, 10.0)
    assert _state(sdk) == 1
    assert sdk.program_pause() == RC_OK
    assert _state(sdk) == 2
    line = sdk.get_current_line()[1]
    assert line in (LINE_OF_THE_LINE, LINE_OF_THE_ARC)
    assert _comes_to_rest(sdk)                             # on the path, paused
    assert sdk.get_current_line() == (RC_OK, line) and _state(sdk) == 2
    assert sdk.program_resume() == RC_OK
    assert _state(sdk) == 1
    assert wait_until(lambda: _state(sdk) == 0, 15.0)
    assert sdk.get_current_line() == (RC_OK, 0)
    assert sdk.get_loaded_program() == (RC_OK, "three_moves.jks")
    assert wait_until(lambda: sdk.get_robot_status()[1].inpos, 2.0)
    assert np.linalg.norm(_tcp_mm(sdk) - THREE_MOVES_END_MM) < 0.5


def test_the_sdk_aborts_a_running_program_and_the_queue_is_empty(sdk):
    assert sdk.program_load("three_moves") == RC_OK and sdk.program_run() == RC_OK
    assert wait_until(lambda: sdk.get_current_line()[1] >= LINE_OF_THE_LINE, 10.0)
    assert sdk.program_abort() == RC_OK              # stop_program, then the queue polled
    assert _state(sdk) == 0 and sdk.get_current_line() == (RC_OK, 0)
    rc, motion = sdk.call("get_motion_state")
    assert rc == RC_OK and motion["queue"] == 0
    assert wait_until(lambda: sdk.get_robot_status()[1].inpos, 2.0)
    assert _comes_to_rest(sdk)                               # nothing more of it runs


def test_a_variable_the_sdk_sets_is_read_back_and_counted_by_the_program(sdk):
    assert sdk.program_load("count_cycles") == RC_OK
    assert sdk.get_user_var() == (RC_OK, [(1, 2.0, "cycles"), (2, 0.0, "done")])
    assert sdk.set_user_var(1, 3.0, "cycles") == RC_OK
    assert json.loads(sdk.sent[-1]) == {"alias_new": "cycles", "cmdName":
                                        "modify_user_defined_variable", "id_new": 1,
                                        "value_new": 3.0}
    assert '"value_new":3.00' in sdk.sent[-1]
    assert sdk.get_user_var()[1][0] == (1, 3.0, "cycles")
    assert sdk.program_run() == RC_OK
    assert wait_until(lambda: _state(sdk) == 0, 5.0)
    assert sdk.get_user_var() == (RC_OK, [(1, 3.0, "cycles"), (2, 3.0, "done")])
    assert sdk.set_user_var(7, 1.0, "x") == RC_FAILED        # no program declares it


def test_the_sdks_circular_move_runs_the_twins_arc_and_refuses_a_line(sdk):
    rc, status = sdk.get_robot_status()
    start = np.array(status.cartesiantran_position)
    mid, end = start.copy(), start.copy()
    mid[:3] += [40.0, 40.0, 0.0]
    end[:3] += [80.0, 0.0, 0.0]
    assert sdk.circular_move(end, mid, ABS, True, 100.0, 500.0, 0.5) == RC_OK
    sent = json.loads(next(t for t in reversed(sdk.sent) if '"movc"' in t))
    assert sorted(sent) == ["accel", "circle_cnt", "circle_mode", "cmdName",
                            "executing_line_id", "pos_end", "pos_mid", "relFlag", "speed",
                            "tol"]
    assert np.linalg.norm(_tcp_mm(sdk) - end[:3]) < 0.5
    line = end.copy()
    line[:3] += [80.0, 0.0, 0.0]
    mid = (end + line) / 2
    assert sdk.circular_move(line, mid, ABS, False, 100.0, 500.0) == RC_FAILED
