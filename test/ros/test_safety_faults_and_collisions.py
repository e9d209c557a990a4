"""Faults on the zu5 twin through ROS: the emergency stop halts the arm and refuses motion until
released, powered and enabled again; a protective stop and a collision with a workcell
obstacle stop a blocking move with -12 and hold until clear_err; inputs can be injected."""
import time

import numpy as np
import pytest
from std_srvs.srv import Empty, SetBool, Trigger

from support.ros_harness import START, at_rest, position, start_driver, wait_until
from jaka_msgs.srv import ClearErr, GetIO, Move, SetCollision, SetIO

pytestmark = pytest.mark.ros

# A post standing 0.55 m in front of the arm, in the way of a joint_1 swing at START.
SCENE = """
obstacles:
  - name: post
    type: box
    size: [0.05, 0.05, 0.6]
    pos: [0.0, 0.55, 0.6]
"""


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node, tmp_path_factory):
    """This module's twin stands in a workcell with a post (overrides conftest's driver, so
    its call / joints fixtures talk to this one)."""
    scene = tmp_path_factory.mktemp("scene") / "post.yaml"
    scene.write_text(SCENE)
    return start_driver(request, backend="sim", model="zu5", scene=str(scene))


def recover(call):
    call("sim/emergency_stop", SetBool, data=False)
    call("power", SetBool, data=True)
    call("enable", SetBool, data=True)
    call("clear_err", ClearErr)


@pytest.fixture(autouse=True)
def at_start(call):
    recover(call)
    reply = call("joint_move", Move, pose=START, mvvelo=2.0, mvacc=8.0)
    assert reply.ret == 1, reply.message


def test_emergency_stop_halts_and_refuses_motion_until_recovered(call, joints, states):
    assert call("sim/emergency_stop", SetBool, data=True).success
    msg = wait_until(lambda: (m := states.latest()) and m.motion_state == 2 and m, 1.0)
    assert msg and msg.power_state == 0
    reply = call("joint_move", Move, pose=[0.3] + START[1:], mvvelo=1.0, mvacc=2.0)
    assert reply.ret == -5, reply.message
    assert call("clear_err", ClearErr).ret == -5
    assert call("sim/emergency_stop", SetBool, data=False).success
    assert call("joint_move", Move, pose=START, mvvelo=1.0, mvacc=2.0).ret == -6
    assert call("power", SetBool, data=True).success
    assert call("joint_move", Move, pose=START, mvvelo=1.0, mvacc=2.0).ret == -7
    assert call("enable", SetBool, data=True).success
    assert call("joint_move", Move, pose=[0.3] + START[1:], mvvelo=1.0, mvacc=2.0).ret == 1


def test_protective_stop_returns_minus_12_to_a_blocking_move(call, joints, states):
    import threading
    replies = []
    mover = threading.Thread(target=lambda: replies.append(
        call("joint_move", Move, pose=[-1.0] + START[1:], mvvelo=0.5, mvacc=2.0)))
    mover.start()
    time.sleep(0.5)
    assert call("sim/protective_stop", Trigger).success
    mover.join(5.0)
    assert replies and replies[0].ret == -12
    q = position(joints)
    # halted where it was: at rest within 0.3 s, a few mrad of momentum at most
    rest = at_rest(joints, timeout=0.3, speed=1e-2)
    assert np.max(np.abs(rest - q)) < 5e-3, "the arm kept moving"
    assert wait_until(lambda: (m := states.latest()) and m.motion_state == 4, 1.0)
    assert call("joint_move", Move, pose=START, mvvelo=1.0, mvacc=2.0).ret == -12
    assert call("clear_err", ClearErr).ret == 1
    assert call("joint_move", Move, pose=START, mvvelo=1.0, mvacc=2.0).ret == 1


def test_collision_with_the_post_stops_the_move_and_raises_the_alarm(call, joints, states):
    assert call("set_collisionlevel", SetCollision, is_enable=True, value=25).ret == 1
    # swing joint_1 from 0 towards +π/2: the forearm meets the post at y = 0.55 m
    reply = call("joint_move", Move, pose=[1.57] + START[1:], mvvelo=0.5, mvacc=2.0)
    assert reply.ret == -12, reply.message
    assert "collision" in reply.message
    msg = wait_until(lambda: (m := states.latest()) and m.collision_state == 1 and m, 1.0)
    assert msg and msg.motion_state == 4
    assert position(joints)[0] < 1.4, "the arm went through the post"
    assert call("jog", Move, coord_mode=0, index=1, mvvelo=0.1).ret == -12
    assert call("clear_err", ClearErr).ret == 1
    assert wait_until(lambda: (m := states.latest()) and m.collision_state == 0, 1.0)
    assert call("joint_move", Move, pose=START, mvvelo=1.0, mvacc=2.0).ret == 1


def test_collision_detection_off_lets_the_arm_push(call, joints):
    assert call("set_collisionlevel", SetCollision, is_enable=False, value=0).ret == 1
    try:
        reply = call("joint_move", Move, pose=[0.6] + START[1:], mvvelo=0.5, mvacc=2.0)
        assert reply.ret != -12 or "collision" not in reply.message
    finally:
        call("stop_move", Empty)
        assert call("set_collisionlevel", SetCollision, is_enable=True, value=50).ret == 1


def test_injected_inputs_are_read_by_get_io(call):
    assert call("sim/set_input", SetIO, signal="digital", type=1, index=1, value=1).ret == 1
    assert call("get_io", GetIO, signal="digital", path=0, type=1, index=1).value == 1.0
    assert call("sim/set_input", SetIO, signal="analog", type=0, index=0, value=3.3).ret == 1
    assert abs(call("get_io", GetIO, signal="analog", path=0, type=0, index=0).value - 3.3) < 1e-6
    assert call("sim/set_input", SetIO, signal="digital", type=0, index=500, value=1).ret == -2
