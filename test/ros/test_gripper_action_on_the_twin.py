"""MoveIt's gripper interface on a real gripper: one node on the zu5 twin in sim time
(real_time_factor 0) with the DH gripper mounted (``_gripper:=dh_pgi``) over
config/scenes/pick.yaml's table and box, the GripperCommand action on ``~gripper/gripper_action``
reaching the twin's gripper only through the tool connector's Modbus frames and signals.

- Started, the node has set the tool connector up (supply on) but nobody has initialised the
  gripper: a goal is aborted at once saying so, and ``~gripper/state`` says powered, not
  initialised.
- ``~gripper/initialise`` then an empty close to 20 mm: succeeded with ``reached_goal`` (grip
  state 1) at 20 mm, not stalled.
- The next goal preempts the one running (a slow open at 1 % speed, preempted by a goal 1 mm
  away, which succeeds).
- With the arm lowered around the box, a close to 0 succeeds ``stalled`` (grip state 2) at the
  box's 57 mm, the state says object held, and the finger joints on ``joint_states`` are half
  the opening each.
"""
from __future__ import annotations

import actionlib
import pytest
import rospy
from control_msgs.msg import GripperCommandAction, GripperCommandGoal
from sensor_msgs.msg import JointState

from jaka_driver.common.models import repo_root
from jaka_driver_msgs.msg import GripperState
from jaka_driver_msgs.srv import InitGripper, SetGripperPercent
from jaka_msgs.srv import Move
from support.ros_harness import Recorder, action_done, start_sim_time_driver, wait_until

pytestmark = pytest.mark.ros

GRASP_DEPTH = (0.4431 - 0.125 - 0.23) * 1000     # mm: the grasp point down to the box's centre
BOX_WIDTH = 0.057                                 # m
Goal = actionlib.GoalStatus


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):   # conftest's call talks to this node
    return start_sim_time_driver(request, gripper="dh_pgi",
                                 scene=str(repo_root() / "config" / "scenes" / "pick.yaml"))


@pytest.fixture(scope="module")
def topics(sim_driver):
    state = Recorder(sim_driver.name("gripper/state"), GripperState)
    joints = Recorder("/joint_states", JointState)
    yield state, joints
    state.close()
    joints.close()


@pytest.fixture(scope="module")
def action(sim_driver):
    client = actionlib.SimpleActionClient(sim_driver.name("gripper/gripper_action"),
                                          GripperCommandAction)
    assert client.wait_for_server(rospy.Duration(10.0))
    yield client


def goal(position: float, effort: float = 0.0) -> GripperCommandGoal:
    g = GripperCommandGoal()
    g.command.position, g.command.max_effort = position, effort
    return g


def finish(client, g: GripperCommandGoal, timeout: float = 20.0):
    client.send_goal(g)
    assert action_done(client, timeout)
    return client.get_state(), client.get_result(), client.get_goal_status_text()


def test_a_goal_is_refused_while_the_gripper_is_not_initialised(action, topics):
    state, _ = topics
    latest = wait_until(state.latest, 5.0)
    assert latest.model == "dh_pgi" and latest.powered and not latest.initialised
    status, _, text = finish(action, goal(0.02))
    assert status == Goal.ABORTED and "not initialised" in text, text


def test_after_initialising_an_empty_close_reaches_its_goal_with_grip_state_1(action, call,
                                                                              topics):
    assert call("gripper/initialise", InitGripper, full_calibration=False).ret == 1
    state, _ = topics
    assert wait_until(lambda: (m := state.latest()) and m.initialised, 10.0)
    status, result, text = finish(action, goal(0.02))
    assert status == Goal.SUCCEEDED, text
    assert result.reached_goal and not result.stalled
    assert result.position == pytest.approx(0.02, abs=0.001)
    assert wait_until(lambda: state.latest().grip_state == 1, 5.0)


def test_the_next_goal_preempts_the_running_one(action, call):
    assert call("gripper/set_speed", SetGripperPercent, percent=1).ret == 1
    try:
        first = goal(0.09)                    # 70 mm at 1 %: over a minute of sim time
        action.send_goal(first)
        assert wait_until(lambda: action.get_state() == Goal.ACTIVE, 5.0)
        second = actionlib.SimpleActionClient(action.action_client.ns, GripperCommandAction)
        assert second.wait_for_server(rospy.Duration(5.0))
        status, result, text = finish(second, goal(0.021))
        assert wait_until(lambda: action.get_state() == Goal.PREEMPTED, 5.0), \
            action.get_goal_status_text()
        assert status == Goal.SUCCEEDED and result.reached_goal, text
    finally:
        assert call("gripper/set_speed", SetGripperPercent, percent=100).ret == 1


def test_closing_on_the_box_answers_stalled_and_the_fingers_are_on_joint_states(action, call,
                                                                                 topics):
    state, joints = topics
    status, _, text = finish(action, goal(0.095))
    assert status == Goal.SUCCEEDED, text
    # down in the tool frame (its z points down at home): the grasp point on the box's centre
    reply = call("linear_move", Move, pose=[0, 0, GRASP_DEPTH, 0, 0, 0], mvvelo=200.0,
                 mvacc=2000.0, coord_mode=2)
    assert reply.ret == 1, reply.message
    status, result, text = finish(action, goal(0.0, 100.0))
    assert status == Goal.SUCCEEDED, text
    assert result.stalled and not result.reached_goal
    assert BOX_WIDTH - 0.001 <= result.position <= BOX_WIDTH + 0.0005
    assert wait_until(lambda: (m := state.latest()).grip_state == 2 and m.object_held, 5.0)
    joints.clear()
    fingers = wait_until(lambda: [m for _, m in joints.samples
                                  if "gripper_finger_left" in m.name], 5.0)
    msg = fingers[-1]
    assert list(msg.name) == ["gripper_finger_left", "gripper_finger_right"]
    assert msg.position[0] == msg.position[1] == pytest.approx(result.position / 2, abs=1e-6)
