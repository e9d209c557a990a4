"""Each backend writes what runs now and the arm's flags in one place:

* on a controller, only controller/running_motion.py keeps a run (a move's watch, a stream, a
  jog) or servo mode; every other module of controller/ writes servo mode as
  ``motion.servo_mode`` and keeps none of the five fields the slot replaced;
* on the twin, only sim/arm_flags.py assigns a flag a RobotState reports (power, enable, servo
  and drag mode, e-stop, protective stop, collision, error), under its name or as ``_name``.

Static reads of the files; nothing is imported or started.
"""
import ast
from dataclasses import fields
from pathlib import Path

from jaka_driver.backend.robot_state import RobotState

SRC = Path(__file__).resolve().parents[2] / "src" / "jaka_driver"
RUN_FIELDS = {"_watch", "_streamer", "_jog", "_twist", "_servo_mode", "servo_mode"}
FLAGS = {"powered", "enabled", "servo_mode", "drag_mode", "emergency_stop", "protective_stop",
         "collision", "error_code", "error_message"}


def assigned_attributes(folder: str, owner: str):
    """(where, the attribute node) of every attribute assigned in ``folder``'s modules but
    ``owner``."""
    for path in sorted((SRC / folder).glob("*.py")):
        if path.name == owner:
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, (ast.AnnAssign, ast.AugAssign)) else []
            for target in targets:
                for t in (target.elts if isinstance(target, ast.Tuple) else [target]):
                    if isinstance(t, ast.Attribute):
                        yield f"{path.name}:{node.lineno} {ast.unparse(t)}", t


def test_no_other_part_of_the_controller_keeps_a_run_or_servo_mode():
    found = [where for where, t in assigned_attributes("controller", "running_motion.py")
             if t.attr in RUN_FIELDS and not (t.attr == "servo_mode"
                                              and isinstance(t.value, ast.Attribute)
                                              and t.value.attr == "motion")]
    assert not found, found


def test_only_arm_flags_writes_a_twin_flag():
    assert FLAGS <= {f.name for f in fields(RobotState)}
    found = [where for where, t in assigned_attributes("sim", "arm_flags.py")
             if t.attr.lstrip("_") in FLAGS]
    assert not found, found
