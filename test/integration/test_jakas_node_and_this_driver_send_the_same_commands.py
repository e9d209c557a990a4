"""The same service calls through JAKA's official ROS node and through this driver in controller
mode put equivalent commands on the wire.

JAKA's binary SDK cannot run here, so its side is restated from the evidence: which SDK call
each service of JAKA's node makes (its node's code) and the request that SDK call writes
(JAKA's SDK 2.1.14 logged byte for byte: compact JSON, keys sorted, ``executing_line_id`` and
``tol`` on every move, ``ori_vel``/``ori_acc`` on moveL, ``stepNum`` on servo commands, IO
index + 1, a setting read back by its get, one ``emergency_stop_status`` inside every move and
jog). This driver's side is what RobotDriver on the
controller backend really sends to the scripted fake controller (test/fake_controller.py).

They are compared by command name, keys and values (poses as positions and rotations, since
RPY has more than one spelling of a rotation). The only differences allowed are the named
conventions in :data:`CONVENTIONS`, each with its reason; any other difference fails.

Twice: with the driver in ``document`` conventions (the requests this driver's document asks
for: rotation vectors, absolute servo targets), and in ``jaka_code`` conventions with exactly
the requests JAKA's node is sent (RPY poses, servo increments, the jog speed in mvacc and
another value in mvvelo), where the servo convention's excuse is gone: the same calls put the
same commands on the wire.
"""
from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field, replace
from typing import Callable, Dict, List, Sequence

import numpy as np
import pytest

from ros_harness import wait_until
from fake_controller import FakeController, start_backend

from jaka_driver.common.transforms import matrix_to_pose, pose_to_matrix, rpy_to_matrix
from jaka_driver.conventions import JAKA_CODE
from jaka_driver.driver import RobotDriver

# ---- the conventions in which the two may differ, and why ----------------------------------------
CONVENTIONS = {
    "e-stop asked": "JAKA's SDK asks emergency_stop_status inside every move and jog (and "
                    "returns 2 where it does not answer, as on the recorded fw 1.5.14); this "
                    "driver reads the e-stop from the status packet, which every firmware on "
                    "record sends",
    "move extras": "JAKA's SDK adds executing_line_id and tol (JAKA's node passes 0.5 mm) to "
                   "every move; the controller ignores unknown keys, and a single blocking "
                   "move has nothing to blend into",
    "orientation limits": "ori_vel/ori_acc: JAKA's node leaves the SDK's defaults (3.14 rad/s, "
                          "12.56 rad/s²); this driver sends its own orientation limits for the "
                          "line's speed (the twin's: speed / 0.1 m, at most π rad/s and "
                          "accel / 0.1 m, at most 2π rad/s²)",
    "move wait": "while a blocking move runs this driver polls get_motion_state (besides the "
                 "status packets' inpos); how JAKA's SDK waits for a blocking move is not in "
                 "the evidence",
    "jog abort": "JAKA's node sends motion_abort (stop_program) before a jog on a new index; "
                 "this driver stops only a jog of another axis (jog mode 0)",
    "jog rotation unit": "JAKA's SDK sends a Cartesian rotation jogvel in rad/s unconverted; "
                         "this driver sends deg/s like the public clients (no controller on "
                         "record settles it)",
    "servo absolute": "JAKA's node sends servo_j/servo_p increments (relFlag 1); this driver "
                      "sends absolute targets (relFlag 0), as JAKA's document says: the target "
                      "is the same pose",
    "step 1": "JAKA's SDK writes stepNum 1; this driver leaves it out when it is 1, the "
              "controller's default",
    "servo off wait": "JAKA's SDK waits for in_servomove true when disabling too (its bug: it "
                      "returns -61); this driver waits for false",
    "increment check": "jaka_code: before a servo_p increment that follows servo_j increments, "
                       "this driver reads the TCP of the last joint target (kine_forward) to "
                       "check the step's speed; JAKA's SDK sends the increment unchecked",
    "frame name": "JAKA's node names every tool 'ToolCoord' and user frame 'BaseCoord'; this "
                  "driver names them by kind and id",
    "frame activated": "this driver activates the frame it stores (set_*_id, read back by "
                       "get_curr_*_id), as JAKA's document says; JAKA's node only stores it",
}

RPY = (math.pi, 0.0, math.pi / 2)   # the fake's TCP orientation, RPY rad


def sdk_move_extras():
    return {"executing_line_id": 0, "tol": 0.5}


#: what JAKA's SDK sends inside joint_move, linear_move, jog and jog_stop after the command
ESTOP_ASKED = {"cmdName": "emergency_stop_status"}


@dataclass
class Case:
    """One service: what this driver does, what JAKA's node's SDK writes for the same call."""
    service: str
    ours: Callable[[RobotDriver], object]
    jaka: List[dict]
    allowed: Dict[str, Sequence[str]] = field(default_factory=dict)
    """convention → the "cmdName.key" (or "+cmdName"/"-cmdName" for a whole command) it
    excuses"""
    reads: Sequence[str] = ()
    """read-back gets JAKA's SDK polls after the set (compared by name: the poll count is the
    controller's timing)"""


def rotvec(rpy) -> List[float]:
    return matrix_to_pose(pose_to_matrix([0, 0, 0, *rpy], rotation="rpy"))[3:].tolist()


Q_TARGET = [0.2, 1.5, -1.4, 1.6, 1.5, 0.1]          # rad
LINE_TARGET_MM = [420.0, -40.0, 310.0]
IK_POSE_MM = [410.0, -50.0, 290.0]
SERVO_STEP = [0.001, 0, 0, 0, 0, 0.001]             # rad, JAKA's own servoj demo step
TOOL = [0.0, 0.0, 100.0, 0.0, 0.0, math.pi / 2]     # mm + RPY rad
USER = [300.0, -200.0, 50.0, 0.0, 0.0, 0.3]


def frame_request(tool_or_user: str, pose_rpy) -> dict:
    return {"cmdName": f"set_{tool_or_user}_offsets", "id": 3,
            "name": "ToolCoord" if tool_or_user == "tool" else "BaseCoord",
            "tooloffset" if tool_or_user == "tool" else "userffset":
                [*pose_rpy[:3], *np.degrees(pose_rpy[3:])]}


CASES = [
    Case("joint_move",
         lambda d: d.joint_move(Q_TARGET, 1.0, 3.0),
         [{"accel": math.degrees(3.0), "cmdName": "joint_move",
           "jointPosition": np.degrees(Q_TARGET).tolist(), "relFlag": 0,
           "speed": math.degrees(1.0), **sdk_move_extras()}, ESTOP_ASKED],
         {"e-stop asked": ["-emergency_stop_status"],
          "move extras": ["joint_move.executing_line_id", "joint_move.tol"],
          "move wait": ["+get_motion_state"]}),
    Case("linear_move",
         # JAKA's node takes RPY (since 2025), this driver the rotation vector: the same pose
         lambda d: d.linear_move([*LINE_TARGET_MM, *rotvec(RPY)], 50.0, 200.0),
         [{"accel": 200.0, "cartPosition": [*LINE_TARGET_MM, *np.degrees(RPY)],
           "cmdName": "moveL", "ori_acc": math.degrees(12.56), "ori_vel": math.degrees(3.14),
           "relFlag": 0, "speed": 50.0, **sdk_move_extras()}, ESTOP_ASKED],
         {"e-stop asked": ["-emergency_stop_status"],
          "move extras": ["moveL.executing_line_id", "moveL.tol"],
          "orientation limits": ["moveL.ori_vel", "moveL.ori_acc"],
          "move wait": ["+get_motion_state"]}),
    Case("jog (joint)",
         lambda d: d.jog(0, 2, 0.2, 0.2),   # joint 2 +, 0.2 rad/s (JAKA's node reads mvacc)
         [{"cmdName": "stop_program"},
          {"cmdName": "jog", "coord_map": 1, "jnum": 1, "jog_mode": 1,
           "jogvel": math.degrees(0.2), "poscmd": 0.0}, ESTOP_ASKED],
         {"jog abort": ["-stop_program"], "e-stop asked": ["-emergency_stop_status"]}),
    Case("jog (linear)",
         lambda d: d.jog(1, 5, 20.0, 20.0),   # base Z-, 20 mm/s
         [{"cmdName": "stop_program"},
          {"cmdName": "jog", "coord_map": 0, "jnum": 2, "jog_mode": 1, "jogvel": -20.0,
           "poscmd": 0.0}, ESTOP_ASKED],
         {"jog abort": ["-stop_program"], "e-stop asked": ["-emergency_stop_status"]}),
    Case("jog (rotation)",
         lambda d: d.jog(2, 10, 0.3, 0.3),   # tool RZ+, 0.3 rad/s
         [{"cmdName": "stop_program"},
          {"cmdName": "jog", "coord_map": 2, "jnum": 5, "jog_mode": 1, "jogvel": 0.3,
           "poscmd": 0.0}, ESTOP_ASKED],
         {"jog abort": ["-stop_program"], "jog rotation unit": ["jog.jogvel"],
          "e-stop asked": ["-emergency_stop_status"]}),
    Case("stop_move",
         lambda d: d.stop_move(),
         [{"cmdName": "stop_program"}]),
    Case("servo_move_enable true",
         lambda d: d.servo_move_enable(True),
         [{"cmdName": "servo_move", "relFlag": 1}], reads=["is_in_servomove"]),
    Case("servo_j",
         lambda d: d.servo_j((d.state().joint_position + SERVO_STEP).tolist()),
         [{"cmdName": "servo_j", "jointPosition": np.degrees(SERVO_STEP).tolist(),
           "relFlag": 1, "stepNum": 1}],
         {"servo absolute": ["servo_j.jointPosition", "servo_j.relFlag"],
          "step 1": ["servo_j.stepNum"]}),
    Case("servo_p",
         # this driver: absolute, m + RPY rad; JAKA's node: an increment, mm + RPY rad
         lambda d: d.servo_p([*(d.state().tcp_pose[:3, 3] + [0.001, 0, 0]), *RPY]),
         [{"catPosition": [1.0, 0.0, 0.0, 0.0, 0.0, 0.0], "cmdName": "servo_p", "relFlag": 1,
           "stepNum": 1}],
         {"servo absolute": ["servo_p.catPosition", "servo_p.relFlag"],
          "step 1": ["servo_p.stepNum"]}),
    Case("servo_move_enable false",
         lambda d: d.servo_move_enable(False),
         [{"cmdName": "servo_move", "relFlag": 0}], {"servo off wait": []},
         reads=["is_in_servomove"]),
    Case("set_toolframe",
         lambda d: d.set_toolframe([*TOOL[:3], *rotvec(TOOL[3:])], 3),
         [frame_request("tool", TOOL)],
         {"frame name": ["set_tool_offsets.name"],
          "frame activated": ["+set_tool_id", "+get_curr_tool_id"]}),
    Case("set_userframe",
         lambda d: d.set_userframe([*USER[:3], *rotvec(USER[3:])], 3),
         [frame_request("user", USER)],
         {"frame name": ["set_user_offsets.name"],
          "frame activated": ["+set_user_id", "+get_curr_user_id"]}),
    Case("set_payload",
         lambda d: d.set_payload(2, 1.5, 0.0, 10.0, 50.0),
         [{"cmdName": "set_tool_id", "tool_id": 2}, {"cmdName": "get_curr_tool_id"},
          {"centroid": [0.0, 10.0, 50.0], "cmdName": "set_payload", "mass": 1.5}],
         reads=["get_curr_tool_id"]),
    Case("drag_move true",
         lambda d: d.drag_mode(True),
         [{"cmdName": "torque_control_enable", "enable_flag": 1}], reads=["get_drag_status"]),
    Case("drag_move false",
         lambda d: d.drag_mode(False),
         [{"cmdName": "torque_control_enable", "enable_flag": 0}], reads=["get_drag_status"]),
    Case("set_collisionlevel",
         lambda d: d.set_collisionlevel(True, 60),   # ≤ 75 → level 3 in both
         [{"cmdName": "set_clsn_sensitivity", "sensitivityVal": 3}]),
    Case("set_io digital",
         lambda d: d.set_io("digital", 0, 2, 1.0),
         [{"cmdName": "set_digital_output", "index": 3, "type": 0, "value": 1}],
         reads=["get_digital_output"]),
    Case("set_io analog",
         lambda d: d.set_io("analog", 0, 1, 2.5),
         [{"cmdName": "set_analog_output", "index": 2, "type": 0, "value": 2.5}],
         reads=["get_analog_output"]),
    Case("get_io digital input",
         lambda d: d.get_io("digital", 0, 1, 1),
         [{"cmdName": "get_digital_input", "index": 2, "type": 1}]),
    Case("get_io analog output",
         lambda d: d.get_io("analog", 1, 0, 1),
         [{"cmdName": "get_analog_output", "index": 2, "type": 0}]),
    Case("get_fk",
         lambda d: d.get_fk(Q_TARGET),
         [{"cmdName": "kine_forward", "jointPosition": np.degrees(Q_TARGET).tolist()}]),
    Case("get_ik",
         lambda d: d.get_ik(Q_TARGET, [*IK_POSE_MM, *rotvec(RPY)]),
         [{"cartPosition": [*IK_POSE_MM, *np.degrees(RPY)], "cmdName": "kine_inverse",
           "jointPosition": np.degrees(Q_TARGET).tolist()}]),
]
POSE_KEYS = {"cartPosition", "catPosition", "tooloffset", "userffset"}

# ---- jaka_code: the calls JAKA's node receives, unchanged ------------------------------------
JAKA_CODE_CALLS = {
    "linear_move": lambda d: d.linear_move([*LINE_TARGET_MM, *RPY], 50.0, 200.0),
    # JAKA's code reads the jog speed from mvacc: mvvelo holds another value, never read
    "jog (joint)": lambda d: d.jog(0, 2, 0.9, 0.2),
    "jog (linear)": lambda d: d.jog(1, 5, 90.0, 20.0),
    "jog (rotation)": lambda d: d.jog(2, 10, 0.9, 0.3),
    "servo_j": lambda d: d.servo_j(SERVO_STEP),
    "servo_p": lambda d: d.servo_p([1.0, 0.0, 0.0, 0.0, 0.0, 0.0]),   # mm + RPY rad
    "get_ik": lambda d: d.get_ik(Q_TARGET, [*IK_POSE_MM, *RPY]),
}
#: the conventions jaka_code mode follows JAKA's code in: no longer differences
FOLLOWED_IN_JAKA_CODE = {"servo absolute"}
JAKA_CODE_CASES = [replace(c, ours=JAKA_CODE_CALLS.get(c.service, c.ours),
                           allowed={**{k: v for k, v in c.allowed.items()
                                       if k not in FOLLOWED_IN_JAKA_CODE},
                                    **({"increment check": ["+kine_forward"]}
                                       if c.service == "servo_p" else {})})
                   for c in CASES]


def same_value(key, ours, jaka) -> bool:
    if key in POSE_KEYS:   # mm + RPY deg: compare positions, and rotations as matrices
        ours, jaka = np.asarray(ours, float), np.asarray(jaka, float)
        return (np.allclose(ours[:3], jaka[:3], atol=1e-6)
                and np.allclose(rpy_to_matrix(*np.radians(ours[3:])),
                                rpy_to_matrix(*np.radians(jaka[3:])), atol=1e-9))
    if isinstance(jaka, (list, tuple)):
        return np.allclose(np.asarray(ours, float), np.asarray(jaka, float), atol=1e-6)
    if isinstance(jaka, (int, float)) and not isinstance(jaka, bool):
        return isinstance(ours, (int, float)) and math.isclose(ours, jaka, abs_tol=1e-6)
    return ours == jaka


def differences(ours: List[dict], case: Case) -> List[str]:
    """What differs between the two, each as "cmdName.key", "+cmd" (only ours) or "-cmd"."""
    found: List[str] = []
    reads = set(case.reads)
    our_names = [r["cmdName"] for r in ours]
    # read-back polls: the count is the controller's timing, the command must be there
    for name in case.reads:
        if name not in our_names:
            found.append(f"-{name}")
    ours = [r for r in ours if r["cmdName"] not in reads]
    jaka = [r for r in case.jaka if r["cmdName"] not in reads]
    jaka_names = [r["cmdName"] for r in jaka]
    found += [f"+{n}" for n in our_names if n not in jaka_names and n not in reads]
    found += [f"-{n}" for n in jaka_names if n not in our_names]
    for expected in jaka:
        name = expected["cmdName"]
        mine = next((r for r in ours if r["cmdName"] == name), None)
        if mine is None:
            continue
        for key in sorted(set(expected) | set(mine)):
            if key not in mine or key not in expected or not same_value(key, mine[key],
                                                                          expected[key]):
                found.append(f"{name}.{key}")
    return found


def _session(**conventions):
    with FakeController(move_time=0.2) as fake:
        backend = start_backend(fake)
        driver = RobotDriver(backend, jog_timeout=30.0, **conventions)
        try:
            yield fake, driver
        finally:
            driver.shutdown()


@pytest.fixture(scope="module")
def session():
    yield from _session()


@pytest.fixture(scope="module")
def jaka_code_session():
    yield from _session(conventions=JAKA_CODE)


@pytest.mark.parametrize("case", CASES, ids=[c.service for c in CASES])
def test_a_service_puts_what_jakas_node_puts_on_the_wire(session, case):
    _compare(session, case)


@pytest.mark.parametrize("case", JAKA_CODE_CASES, ids=[c.service for c in JAKA_CODE_CASES])
def test_jakas_calls_in_jaka_code_mode_put_what_jakas_node_puts_on_the_wire(jaka_code_session,
                                                                            case):
    _compare(jaka_code_session, case)


def test_jaka_code_mode_needs_no_servo_or_orientation_excuse():
    for case in JAKA_CODE_CASES:
        assert not FOLLOWED_IN_JAKA_CODE & set(case.allowed), case.service


def _compare(session, case: Case) -> None:
    fake, driver = session
    # the previous case's move may still have its get_motion_state follower about to poll once
    # more: let it end, so its request is not counted as this service's
    assert wait_until(lambda: not any(t.name == "jaka-motion-state" and t.is_alive()
                                      for t in threading.enumerate()), 2.0)
    with fake.lock:
        before = len(fake.requests)
    result = case.ours(driver)
    with fake.lock:
        ours = [dict(r) for r in fake.requests[before:]]
    excused = {item for items in case.allowed.values() for item in items}
    found = differences(ours, case)
    unexplained = [d for d in found if d not in excused]
    assert not unexplained, (f"{case.service}: {unexplained} differ from JAKA's node; this "
                             f"driver sent {ours}, JAKA's SDK writes {case.jaka} ({result})")
    for convention in case.allowed:
        assert convention in CONVENTIONS
    # the ones excused are really there: a convention that no longer differs is removed
    for item in excused:
        assert item in found, f"{case.service}: {item} no longer differs; drop the excuse"
    if case.service.startswith("jog"):
        driver.stop_move()


def test_every_service_of_jakas_node_is_compared():
    # JAKA's node's services (its code): clear_err is documented there but not served
    served = {"joint_move", "linear_move", "jog", "stop_move", "servo_move_enable", "servo_j",
              "servo_p", "set_toolframe", "set_userframe", "set_payload", "drag_move",
              "set_collisionlevel", "set_io", "get_io", "get_fk", "get_ik"}
    compared = {c.service.split(" ")[0] for c in CASES}
    assert compared == served


def test_the_orientation_limits_follow_the_lines_speed_up_to_the_twins_caps(session):
    fake, driver = session
    for speed, accel in ((10.0, 50.0), (250.0, 2500.0), (1000.0, 10000.0)):   # mm/s, mm/s²
        assert driver.linear_move([*LINE_TARGET_MM[:2], 300.0 + speed / 100, *rotvec(RPY)],
                                  speed, accel).ok
        sent = fake.received("moveL")[-1]
        # a point 0.1 m from the axis moves at the line's speed (π rad/s, 2π rad/s² at most)
        assert sent["ori_vel"] == pytest.approx(min(speed / 100.0, math.pi) * 180 / math.pi)
        assert sent["ori_acc"] == pytest.approx(min(accel / 100.0, 2 * math.pi) * 180 / math.pi)
