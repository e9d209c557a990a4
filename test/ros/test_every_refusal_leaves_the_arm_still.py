"""Every refusal class (docs/interface.md, "Result codes") through ROS on the zu5 twin: the reply
says so (``ret`` -2, or the failure markers of get_io / get_fk / get_ik) with a message naming the
field, the value and the limit — and the arm did not move and nothing changed: same joints (no
velocity after the call), same robot_states, same active tool and user frame (tool_position
frame_id, get_fk), same payload (joint efforts), same IO outputs.

The module runs with a non-trivial setting active — tool 1 offset 100 mm along the flange z,
user frame 1 shifted and turned, a 2 kg payload, two IO outputs set — so a refused request
that leaked into any of them would show.
"""
import time

import numpy as np
import pytest
from std_srvs.srv import Empty, SetBool

from support.ros_harness import START, at_rest, go_home, wait_until
from jaka_msgs.srv import (ClearErr, GetFK, GetIK, GetIO, Move, ServoMove, ServoMoveEnable,
                           SetCollision, SetIO, SetPayload, SetTcpFrame, SetUserFrame)

pytestmark = pytest.mark.ros

TOOL_1 = [0.0, 0.0, 100.0, 0.0, 0.0, 0.0]             # mm + rotvec, flange frame
USER_1 = [100.0, 200.0, 0.0, 0.0, 0.0, 0.3]           # mm + rotvec, base frame
PAYLOAD = dict(tool_num=1, mass=2.0, xc=0.0, yc=0.0, zc=50.0)
# outputs of the twin (config/zu5.yaml): (signal, type, count)
OUTPUTS = [("digital", 0, 16), ("analog", 0, 2), ("digital", 1, 2), ("digital", 2, 8),
           ("analog", 2, 4)]
SET_OUTPUTS = [("digital", 0, 3, 1.0), ("analog", 2, 1, 2.5)]

NAN, INF = float("nan"), float("inf")
STILL = 1e-4          # rad: the arm holding still drifts far less than this
QUIET = 1e-3          # rad/s: no joint may move faster than this after a refused request


@pytest.fixture(scope="module", autouse=True)
def busy_settings(call, joints):
    """START, with a tool, a user frame, a payload and IO outputs active; undone at the end."""
    call("sim/emergency_stop", SetBool, data=False)
    call("power", SetBool, data=True)
    call("enable", SetBool, data=True)
    call("clear_err", ClearErr)
    go_home(call)
    assert call("set_toolframe", SetTcpFrame, pose=TOOL_1, tool_num=1).ret == 1
    assert call("set_userframe", SetUserFrame, pose=USER_1, user_num=1).ret == 1
    assert call("set_payload", SetPayload, **PAYLOAD).ret == 1
    for signal, io_type, index, value in SET_OUTPUTS:
        assert call("set_io", SetIO, signal=signal, type=io_type, index=index,
                    value=value).ret == 1
    yield
    call("servo_move_enable", ServoMoveEnable, enable=False)
    call("stop_move", Empty)
    call("set_payload", SetPayload, tool_num=0, mass=0.0, xc=0.0, yc=0.0, zc=0.0)
    call("set_toolframe", SetTcpFrame, pose=[0.0] * 6, tool_num=0)
    call("set_userframe", SetUserFrame, pose=[0.0] * 6, user_num=0)
    for signal, io_type, index, _ in SET_OUTPUTS:
        call("set_io", SetIO, signal=signal, type=io_type, index=index, value=0.0)


def fresh(recorder, t0: float):
    """The first message received after ``t0`` (so a mode just set is seen)."""
    got = wait_until(lambda: recorder.since(t0), 2.0)
    assert got, "a state topic is silent"
    return got[0][1]


def steady_effort(joints, t0: float) -> np.ndarray:
    """Joint efforts (N·m) of a sample received after ``t0``, once they hold within 0.2 N·m
    over 0.1 s. The latest sample alone was not enough for the module's first case: it could
    predate the payload the fixture had just set (~10 N·m on the shoulder) or catch the drives
    still taking it up."""
    def steady():
        got = joints.since(t0)
        if len(got) < 2:
            return None
        last_t, last = got[-1]
        earlier = [m for t, m in got if t <= last_t - 0.1]
        if earlier and np.max(np.abs(np.array(earlier[-1].effort)
                                     - np.array(last.effort))) < 0.2:
            return [np.array(last.effort)]      # a list: truthy even if every effort is 0
        return None

    effort = wait_until(steady, 5.0)
    assert effort, "the joint efforts did not settle within 5 s"
    return effort[0]


def snapshot(call, joints, states, tcp) -> dict:
    """What a refused request must leave as it was; joints measured once at rest."""
    t0 = time.time()
    q = at_rest(joints)
    effort = steady_effort(joints, t0)
    outputs = {(sig, t, i): call("get_io", GetIO, signal=sig, path=1, type=t, index=i).value
               for sig, t, n in OUTPUTS for i in range(n)}
    # a message sampled after the last request, not one still in flight from before it
    st, tcp = fresh(states, t0 + 0.05), fresh(tcp, t0 + 0.05)
    return dict(q=q, effort=effort, frame_id=tcp.header.frame_id,
                fk=np.array(call("get_fk", GetFK, joint=START).cartesian_pose),
                states=(st.motion_state, st.power_state, st.servo_state, st.collision_state),
                outputs=outputs)


def assert_nothing_changed(before: dict, after: dict, motion: list) -> None:
    moved = np.max(np.abs(after["q"] - before["q"]))
    assert moved < STILL, f"the arm moved {moved:.2e} rad"
    fastest = max((np.max(np.abs(m.velocity)) for _, m in motion), default=0.0)
    assert fastest < QUIET, f"a joint moved at {fastest:.2e} rad/s after the refusal"
    assert after["frame_id"] == before["frame_id"], "the active user frame changed"
    assert np.allclose(after["fk"], before["fk"], atol=1e-3), "the active tool or user changed"
    assert after["states"] == before["states"], "robot_states changed"
    assert after["outputs"] == before["outputs"], "an IO output changed"
    # 2 kg held out ~0.5 m: a payload change shows as tens of N·m on the shoulder
    assert np.max(np.abs(after["effort"] - before["effort"])) < 1.0, "the payload changed"


SERVO_STEP = [START[0] + 0.2] + START[1:]        # 0.2 rad in 8 ms = 25 rad/s on joint_1


#: Placeholder for a servo_p target 100 mm above the TCP (12 500 mm/s in one cycle), filled
#: in at run time from the current tool_position (m + rotvec → m + RPY).
FAR_ABOVE = "100 mm above the TCP"


# (id, service, type, fields, mode, words): ``words`` must all be in the message; ``mode``
# "servo" runs the request in servo mode (servo_j / servo_p), else with servo mode off.
CASES = [
    # ---- wrong array length ----
    ("joint_move pose 5", "joint_move", Move, dict(pose=START[:5], mvvelo=1.0, mvacc=2.0),
     None, ["pose has 5 values", "expected 6"]),
    ("joint_move pose 7", "joint_move", Move, dict(pose=START + [0.0], mvvelo=1.0, mvacc=2.0),
     None, ["pose has 7 values", "expected 6"]),
    ("linear_move pose 0", "linear_move", Move, dict(pose=[], mvvelo=10.0, mvacc=100.0),
     None, ["pose has 0 values", "expected 6"]),
    ("linear_move ref_joint 5", "linear_move", Move,
     dict(pose=[0, 0, 1.0, 0, 0, 0], mvvelo=10.0, mvacc=100.0, coord_mode=2, has_ref=True,
          ref_joint=START[:5]), None, ["ref_joint has 5 values", "expected 6"]),
    ("servo_j pose 3", "servo_j", ServoMove, dict(pose=START[:3], speed=[]), "servo",
     ["pose has 3 values", "expected 6"]),
    ("servo_p pose 8", "servo_p", ServoMove, dict(pose=[0.0] * 8, speed=[]), "servo",
     ["pose has 8 values", "expected 6"]),
    ("set_toolframe pose 5", "set_toolframe", SetTcpFrame, dict(pose=[0.0] * 5, tool_num=2),
     None, ["pose has 5 values", "expected 6"]),
    ("set_userframe pose 12", "set_userframe", SetUserFrame, dict(pose=[0.0] * 12, user_num=2),
     None, ["pose has 12 values", "expected 6"]),
    ("get_fk joint 5", "get_fk", GetFK, dict(joint=START[:5]), None,
     ["joint has 5 values", "expected 6"]),
    ("get_ik pose 5", "get_ik", GetIK, dict(ref_joint=START, cartesian_pose=[0.0] * 5), None,
     ["cartesian_pose has 5 values", "expected 6"]),
    ("get_ik ref_joint 2", "get_ik", GetIK,
     dict(ref_joint=START[:2], cartesian_pose=[400.0, 0, 400, 3.14, 0, 0]), None,
     ["ref_joint has 2 values", "expected 6"]),
    # ---- NaN / inf ----
    ("joint_move pose nan", "joint_move", Move,
     dict(pose=START[:2] + [NAN] + START[3:], mvvelo=1.0, mvacc=2.0), None,
     ["pose[2] is nan", "finite"]),
    ("joint_move mvvelo inf", "joint_move", Move, dict(pose=START, mvvelo=INF, mvacc=2.0),
     None, ["mvvelo is inf", "finite"]),
    ("joint_move mvacc -inf", "joint_move", Move, dict(pose=START, mvvelo=1.0, mvacc=-INF),
     None, ["mvacc is -inf", "finite"]),
    ("joint_move mvtime nan", "joint_move", Move,
     dict(pose=START, mvvelo=1.0, mvacc=2.0, mvtime=NAN), None, ["mvtime is nan", "finite"]),
    ("linear_move pose inf", "linear_move", Move,
     dict(pose=[INF, 0, 0, 0, 0, 0], mvvelo=10.0, mvacc=100.0, coord_mode=2), None,
     ["pose[0] is inf", "finite"]),
    ("linear_move mvvelo nan", "linear_move", Move,
     dict(pose=[0, 0, 1.0, 0, 0, 0], mvvelo=NAN, mvacc=100.0, coord_mode=2), None,
     ["mvvelo is nan", "finite"]),
    ("jog mvvelo nan", "jog", Move, dict(coord_mode=0, index=0, mvvelo=NAN), None,
     ["mvvelo is nan", "finite"]),
    ("servo_j nan", "servo_j", ServoMove, dict(pose=[NAN] + START[1:], speed=[]), "servo",
     ["pose[0] is nan", "finite"]),
    ("servo_p inf", "servo_p", ServoMove, dict(pose=[0.4, 0, 0.4, 0, INF, 0], speed=[]),
     "servo", ["pose[4] is inf", "finite"]),
    ("set_toolframe nan", "set_toolframe", SetTcpFrame,
     dict(pose=[0, 0, NAN, 0, 0, 0], tool_num=1), None, ["pose[2] is nan", "finite"]),
    ("set_userframe inf", "set_userframe", SetUserFrame,
     dict(pose=[0, 0, 0, 0, 0, -INF], user_num=1), None, ["pose[5] is -inf", "finite"]),
    ("get_fk nan", "get_fk", GetFK, dict(joint=[NAN] * 6), None, ["joint[0] is nan", "finite"]),
    ("get_ik inf", "get_ik", GetIK, dict(ref_joint=START, cartesian_pose=[INF] * 6), None,
     ["cartesian_pose[0] is inf", "finite"]),
    ("set_io value nan", "set_io", SetIO, dict(signal="analog", type=0, index=0, value=NAN),
     None, ["value is nan", "finite"]),
    # ---- out-of-range joints (model limits, zu5: joint_3 ±3.05, joint_2 -1.48…4.62) ----
    ("joint_move joint_3 3.4", "joint_move", Move,
     dict(pose=START[:2] + [3.4] + START[3:], mvvelo=1.0, mvacc=2.0), None,
     ["joint_3 target 3.4000 rad", "[-3.05, 3.05]"]),
    ("joint_move joint_2 -1.6", "joint_move", Move,
     dict(pose=[START[0], -1.6] + START[2:], mvvelo=1.0, mvacc=2.0), None,
     ["joint_2 target -1.6000 rad", "[-1.48, 4.62]"]),
    ("joint_move joint_1 7", "joint_move", Move,
     dict(pose=[7.0] + START[1:], mvvelo=1.0, mvacc=2.0), None,
     ["joint_1 target 7.0000 rad", "[-6.28, 6.28]"]),
    ("linear_move ref_joint out", "linear_move", Move,
     dict(pose=[0, 0, 1.0, 0, 0, 0], mvvelo=10.0, mvacc=100.0, coord_mode=2, has_ref=True,
          ref_joint=START[:2] + [-3.2] + START[3:]), None,
     ["joint_3 target -3.2000 rad", "[-3.05, 3.05]"]),
    ("servo_j joint_3 out", "servo_j", ServoMove,
     dict(pose=START[:2] + [3.1] + START[3:], speed=[]), "servo",
     ["joint_3 target 3.1000 rad", "[-3.05, 3.05]"]),
    # ---- tool 0–11 / user 0–10 ----
    ("set_toolframe tool 12", "set_toolframe", SetTcpFrame, dict(pose=[0.0] * 6, tool_num=12),
     None, ["tool_num is 12", "expected 0–11"]),
    ("set_toolframe tool -1", "set_toolframe", SetTcpFrame, dict(pose=[0.0] * 6, tool_num=-1),
     None, ["tool_num is -1", "expected 0–11"]),
    ("set_userframe user 11", "set_userframe", SetUserFrame, dict(pose=[0.0] * 6, user_num=11),
     None, ["user_num is 11", "expected 0–10"]),
    ("set_userframe user -1", "set_userframe", SetUserFrame, dict(pose=[0.0] * 6, user_num=-1),
     None, ["user_num is -1", "expected 0–10"]),
    ("set_payload tool 12", "set_payload", SetPayload,
     dict(tool_num=12, mass=1.0, xc=0, yc=0, zc=0), None, ["tool_num is 12", "expected 0–11"]),
    ("set_toolframe too far", "set_toolframe", SetTcpFrame,
     dict(pose=[0, 0, 1500.0, 0, 0, 0], tool_num=2), None, ["1500.0 mm", "limit 1000 mm"]),
    ("set_userframe too far", "set_userframe", SetUserFrame,
     dict(pose=[20000.0, 0, 0, 0, 0, 0], user_num=2), None, ["20000.0 mm", "limit 10000 mm"]),
    # ---- collision value 10–100 ----
    ("collision 9", "set_collisionlevel", SetCollision, dict(is_enable=True, value=9), None,
     ["value is 9", "expected 10–100"]),
    ("collision 101", "set_collisionlevel", SetCollision, dict(is_enable=True, value=101), None,
     ["value is 101", "expected 10–100"]),
    ("collision -50", "set_collisionlevel", SetCollision, dict(is_enable=True, value=-50), None,
     ["value is -50", "expected 10–100"]),
    # ---- IO signal / type / index / path ----
    ("set_io signal", "set_io", SetIO, dict(signal="digtal", type=0, index=3, value=0), None,
     ["signal is 'digtal'", "'digital' or 'analog'"]),
    ("set_io empty signal", "set_io", SetIO, dict(signal="", type=0, index=3, value=0), None,
     ["signal is ''", "'digital' or 'analog'"]),
    ("set_io type 3", "set_io", SetIO, dict(signal="digital", type=3, index=3, value=0), None,
     ["type is 3", "expected 0–2"]),
    ("set_io type -1", "set_io", SetIO, dict(signal="digital", type=-1, index=3, value=0), None,
     ["type is -1", "expected 0–2"]),
    ("set_io index 16", "set_io", SetIO, dict(signal="digital", type=0, index=16, value=0),
     None, ["index is 16", "0–15"]),
    ("set_io index -1", "set_io", SetIO, dict(signal="analog", type=2, index=-1, value=0),
     None, ["index is -1", "0–3"]),
    ("set_io tool analog out", "set_io", SetIO, dict(signal="analog", type=1, index=0, value=1),
     None, ["tool analog outputs do not exist", "index 0"]),
    ("set_io analog 12 V", "set_io", SetIO, dict(signal="analog", type=2, index=1, value=12.0),
     None, ["value is 12", "±10 V"]),
    ("get_io path 2", "get_io", GetIO, dict(signal="digital", path=2, type=0, index=0), None,
     ["path is 2", "expected 0–1"]),
    ("get_io signal", "get_io", GetIO, dict(signal="pneumatic", path=0, type=0, index=0), None,
     ["signal is 'pneumatic'", "'digital' or 'analog'"]),
    ("get_io type 7", "get_io", GetIO, dict(signal="analog", path=0, type=7, index=0), None,
     ["type is 7", "expected 0–2"]),
    ("get_io index 8", "get_io", GetIO, dict(signal="digital", path=0, type=2, index=8), None,
     ["index is 8", "0–7"]),
    ("set_input index 2", "sim/set_input", SetIO, dict(signal="digital", type=1, index=2,
                                                        value=1), None, ["index is 2", "0–1"]),
    # ---- mass and centroid ----
    ("mass 7.6", "set_payload", SetPayload, dict(tool_num=1, mass=7.6, xc=0, yc=0, zc=50),
     None, ["mass is 7.6 kg", "0–7.5 kg"]),
    ("mass -0.5", "set_payload", SetPayload, dict(tool_num=1, mass=-0.5, xc=0, yc=0, zc=50),
     None, ["mass is -0.5 kg", "0–7.5 kg"]),
    ("mass nan", "set_payload", SetPayload, dict(tool_num=1, mass=NAN, xc=0, yc=0, zc=50),
     None, ["mass is nan", "finite"]),
    ("centroid 1200", "set_payload", SetPayload,
     dict(tool_num=1, mass=1.0, xc=0, yc=0, zc=1200.0), None,
     ["centroid is 1200.0 mm", "limit 1000 mm"]),
    ("centroid inf", "set_payload", SetPayload, dict(tool_num=1, mass=1.0, xc=INF, yc=0, zc=0),
     None, ["xc is inf", "finite"]),
    # ---- speeds ≤ 0 or absurd (> 10× the limit) ----
    ("joint_move mvvelo 0", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=0.0, mvacc=2.0), None,
     ["mvvelo is 0 rad/s", "expected > 0", "3.14 rad/s"]),
    ("joint_move mvvelo -1", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=-1.0, mvacc=2.0), None,
     ["mvvelo is -1 rad/s", "expected > 0", "3.14 rad/s"]),
    ("joint_move mvvelo 40", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=40.0, mvacc=2.0), None,
     ["mvvelo is 40 rad/s", "10× the model limit 3.14 rad/s"]),
    ("joint_move mvacc -2", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=1.0, mvacc=-2.0), None,
     ["mvacc is -2 rad/s²", "expected > 0"]),
    ("joint_move mvacc 200", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=1.0, mvacc=200.0), None,
     ["mvacc is 200 rad/s²", "10× the model limit 12.57 rad/s²"]),
    ("joint_move mvtime -1", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=1.0, mvacc=2.0, mvtime=-1.0), None,
     ["mvtime is -1 s", "expected ≥ 0"]),
    ("joint_move mvtime too short", "joint_move", Move,
     dict(pose=[0.3] + START[1:], mvvelo=1.0, mvacc=2.0, mvtime=0.05), None,
     ["mvtime is 0.050 s", "0.775 s this move needs"]),

    ("linear_move mvvelo 0", "linear_move", Move,
     dict(pose=[0, 0, 5.0, 0, 0, 0], mvvelo=0.0, mvacc=100.0, coord_mode=2), None,
     ["mvvelo is 0 mm/s", "expected > 0", "3000 mm/s"]),
    ("linear_move mvvelo 30001", "linear_move", Move,
     dict(pose=[0, 0, 5.0, 0, 0, 0], mvvelo=30001.0, mvacc=100.0, coord_mode=2), None,
     ["mvvelo is 30001 mm/s", "10× the model limit 3000 mm/s"]),
    ("linear_move mvacc -100", "linear_move", Move,
     dict(pose=[0, 0, 5.0, 0, 0, 0], mvvelo=10.0, mvacc=-100.0, coord_mode=2), None,
     ["mvacc is -100 mm/s²", "expected > 0"]),
    ("linear_move coord_mode 3", "linear_move", Move,
     dict(pose=[0, 0, 5.0, 0, 0, 0], mvvelo=10.0, mvacc=100.0, coord_mode=3), None,
     ["coord_mode is 3", "expected 0–2"]),
    ("jog mvvelo -0.1", "jog", Move, dict(coord_mode=0, index=0, mvvelo=-0.1), None,
     ["mvvelo is -0.1 rad/s", "expected > 0"]),
    ("jog mvvelo 0 mvacc 0", "jog", Move, dict(coord_mode=0, index=2, mvvelo=0.0, mvacc=0.0),
     None, ["mvvelo is 0 rad/s", "expected > 0"]),
    ("jog mvvelo 40 rad/s", "jog", Move, dict(coord_mode=0, index=4, mvvelo=40.0), None,
     ["mvvelo is 40 rad/s", "10× the model limit 3.14 rad/s"]),
    ("jog mvacc as speed -5", "jog", Move, dict(coord_mode=1, index=0, mvvelo=0.0, mvacc=-5.0),
     None, ["mvvelo is 0 mm/s", "expected > 0"]),
    ("jog X 50000 mm/s", "jog", Move, dict(coord_mode=1, index=1, mvvelo=50000.0), None,
     ["mvvelo is 50000 mm/s", "10× the model limit 3000 mm/s"]),
    ("jog RZ 40 rad/s", "jog", Move, dict(coord_mode=2, index=11, mvvelo=40.0), None,
     ["mvvelo is 40 rad/s", "limit 3.14159 rad/s"]),
    ("jog coord_mode 3", "jog", Move, dict(coord_mode=3, index=0, mvvelo=0.1), None,
     ["coord_mode is 3", "expected 0–2"]),
    ("jog index 12", "jog", Move, dict(coord_mode=0, index=12, mvvelo=0.1), None,
     ["index is 12", "expected 0–11"]),
    # ---- servo steps that imply over-speed ----
    ("servo_j 25 rad/s", "servo_j", ServoMove, dict(pose=SERVO_STEP, speed=[]), "servo",
     ["joint_1 step of 0.2000 rad", "25.00 rad/s", "limit 3.14 rad/s"]),
    ("servo_p 12500 mm/s", "servo_p", ServoMove, dict(pose=FAR_ABOVE, speed=[]), "servo",
     ["pose step needs 12500 mm/s", "limit 3000 mm/s"]),
]


def refused(service: str, reply) -> bool:
    """The failure marker of each reply type (docs/interface.md, "Result codes")."""
    if service == "get_io":
        return reply.value == -999999 and reply.message.startswith("error:")
    if service == "get_fk":
        return list(reply.cartesian_pose) == [9999] * 6 and reply.message.startswith("error:")
    if service == "get_ik":
        return list(reply.joint) == [9999] * 6 and reply.message.startswith("error:")
    return reply.ret == -2


def servo_p_target_100_mm_away(tcp) -> list:
    from jaka_driver.common.transforms import matrix_to_rpy, rotvec_to_matrix
    msg = wait_until(tcp.latest, 2.0)
    p = [msg.twist.linear.x, msg.twist.linear.y, msg.twist.linear.z + 0.1]
    a = msg.twist.angular
    return p + list(matrix_to_rpy(rotvec_to_matrix([a.x, a.y, a.z])))


def _case_id(case) -> str:
    return (case.values[0] if hasattr(case, "values") else case)[0]


@pytest.mark.parametrize("case", CASES, ids=[_case_id(c) for c in CASES])
def test_refusal_names_the_field_and_leaves_the_arm_still(case, call, joints, states,
                                                         tcp):
    _, service, srv, fields, mode, words = case
    fields = dict(fields)
    servo = mode == "servo"
    assert call("servo_move_enable", ServoMoveEnable, enable=servo).ret == 1
    if fields.get("pose") == FAR_ABOVE:
        fields["pose"] = servo_p_target_100_mm_away(tcp)
    try:
        before = snapshot(call, joints, states, tcp)
        t_call = time.time()
        reply = call(service, srv, **fields)
        assert refused(service, reply), reply
        for word in words:
            assert word in reply.message, f"{word!r} not in {reply.message!r}"
        time.sleep(0.2)
        motion = joints.since(t_call)
        after = snapshot(call, joints, states, tcp)
        assert_nothing_changed(before, after, motion)
    finally:
        if servo:
            call("servo_move_enable", ServoMoveEnable, enable=False)


# Absurdly slow: a speed or time that would make the move last for ages (units mistakes).
# Without the 10-min cap (move_duration.py) the planner would try to allocate its 8 ms samples
# (gigabytes, or a failed allocation answering -3) and plan for minutes that stop_move cannot
# interrupt; with it the door refuses them with -2 naming the field.
SLOW_CASES = [
    ("joint_move mvvelo 1e-38", "joint_move",
     dict(pose=[0.3] + START[1:], mvvelo=1e-38, mvacc=2.0), "mvvelo"),
    ("joint_move mvacc 1e-38", "joint_move",
     dict(pose=[0.3] + START[1:], mvvelo=1.0, mvacc=1e-38), "mvacc"),
    ("joint_move mvtime 3e38", "joint_move",
     dict(pose=[0.3] + START[1:], mvvelo=1.0, mvacc=2.0, mvtime=3e38), "mvtime"),
    ("linear_move mvvelo 1e-38", "linear_move",
     dict(pose=[0, 0, 5.0, 0, 0, 0], mvvelo=1e-38, mvacc=100.0, coord_mode=2), "mvvelo"),
]


@pytest.mark.parametrize("case", SLOW_CASES, ids=[c[0] for c in SLOW_CASES])
def test_absurdly_slow_move_is_refused_and_the_arm_stays_still(case, call, joints, states,
                                                              tcp):
    _, service, fields, field = case
    assert call("servo_move_enable", ServoMoveEnable, enable=False).ret == 1
    before = snapshot(call, joints, states, tcp)
    t_call = time.time()
    reply = call(service, Move, **fields)
    time.sleep(0.2)
    motion = joints.since(t_call)
    after = snapshot(call, joints, states, tcp)
    assert_nothing_changed(before, after, motion)
    assert reply.ret == -2, reply.message
    assert field in reply.message and "limit" in reply.message, reply.message
