"""The twin's arm flags have one writer, sim/arm_flags.py (ArmFlags): no other module of sim/
assigns a flag a RobotState reports (power, enable, servo and drag mode, e-stop, protective
stop, collision, error), under its name or as a private ``_name``. Static reads; nothing is
imported."""
import ast
from dataclasses import fields
from pathlib import Path

from jaka_driver.backend.robot_state import RobotState

SIM = Path(__file__).resolve().parents[2] / "src" / "jaka_driver" / "sim"
FLAGS = {"powered", "enabled", "servo_mode", "drag_mode", "emergency_stop", "protective_stop",
         "collision", "error_code", "error_message"}


def test_the_flags_are_robot_states_own():
    assert FLAGS <= {f.name for f in fields(RobotState)}


def test_only_arm_flags_writes_a_flag():
    found = []
    for path in sorted(SIM.glob("*.py")):
        if path.name == "arm_flags.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, (ast.AnnAssign, ast.AugAssign)) else []
            for target in targets:
                for t in (target.elts if isinstance(target, ast.Tuple) else [target]):
                    if isinstance(t, ast.Attribute) and t.attr.lstrip("_") in FLAGS:
                        found.append(f"{path.name}:{node.lineno} {ast.unparse(t)}")
    assert not found, found
