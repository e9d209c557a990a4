"""The FollowJointTrajectory action on the zu5 twin, with actionlib's SimpleActionClient: a
3-point trajectory succeeds and the measured path follows the interpolated reference; wrong
joints are INVALID_JOINTS; a cancel stops the arm and is not SUCCESSFUL; an impossible path
tolerance is PATH_TOLERANCE_VIOLATED; servo mode refuses the goal."""
import time

import actionlib
import numpy as np
import pytest
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal,
                              FollowJointTrajectoryResult, JointTolerance)
from std_srvs.srv import Empty
from trajectory_msgs.msg import JointTrajectoryPoint

from support.ros_harness import START, at_rest, go_home, position, stamp, wait_until
from jaka_msgs.srv import Move, ServoMoveEnable

from jaka_driver.motion.spline import Waypoint, sample_waypoints

pytestmark = pytest.mark.ros

NAMES = [f"joint_{i}" for i in range(1, 7)]
R = FollowJointTrajectoryResult


@pytest.fixture(scope="module")
def client(sim_driver, rospy_node):
    c = actionlib.SimpleActionClient(sim_driver.name("follow_joint_trajectory"),
                                     FollowJointTrajectoryAction)
    assert c.wait_for_server(rospy.Duration(10))
    return c


@pytest.fixture(autouse=True)
def at_start(call):
    go_home(call)

def goal_through(points, names=NAMES, path_tolerance=None):
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = names
    for t, q in points:
        goal.trajectory.points.append(JointTrajectoryPoint(
            positions=q, velocities=[0.0] * 6, time_from_start=rospy.Duration(t)))
    if path_tolerance is not None:
        goal.path_tolerance = [JointTolerance(name=n, position=path_tolerance) for n in NAMES]
    return goal


THREE_POINTS = [(1.0, [0.3, 1.4, -1.4, 1.6, 1.6, 0.2]),
                (2.0, [0.6, 1.3, -1.2, 1.7, 1.5, 0.4]),
                (3.0, [0.4, 1.5, -1.3, 1.5, 1.7, 0.1])]


def test_three_points_succeed_and_the_path_stays_within_1e2_rad(client, joints):
    t0 = time.time()
    client.send_goal(goal_through(THREE_POINTS))
    assert client.wait_for_result(rospy.Duration(10))
    assert client.get_state() == GoalStatus.SUCCEEDED
    assert client.get_result().error_code == R.SUCCESSFUL
    samples = joints.since(t0)
    stamps = np.array([m.header.stamp.to_sec() for _, m in samples])
    q = np.array([m.position for _, m in samples])
    times, ref_q, _ = sample_waypoints(np.array(START), [
        Waypoint(t, np.array(p), np.zeros(6)) for t, p in THREE_POINTS], 0.008)

    def worst_error(start_time):
        during = (stamps >= start_time) & (stamps <= start_time + 3.0)
        expected = np.column_stack([np.interp(stamps[during] - start_time, times, ref_q[:, j])
                                    for j in range(6)])
        return np.max(np.abs(q[during] - expected))

    # The client cannot know when the server started the motion: take the best alignment
    # within ±0.2 s of the first visible movement.
    moving = np.nonzero(np.max(np.abs(q - START), axis=1) > 1e-3)[0]
    first = stamps[moving[0]]
    best = min(worst_error(first + dt) for dt in np.arange(-0.2, 0.2, 0.001))
    assert best <= 1e-2, f"max deviation from the interpolated reference {best:.4f} rad"
    assert np.max(np.abs(position(joints) - THREE_POINTS[-1][1])) < 2e-3


def test_wrong_joint_names_are_invalid_joints(client, joints):
    before = at_rest(joints)
    client.send_goal(goal_through(THREE_POINTS, names=NAMES[:5] + ["wrist_3"]))
    assert client.wait_for_result(rospy.Duration(5))
    assert client.get_result().error_code == R.INVALID_JOINTS
    assert np.max(np.abs(position(joints) - before)) < 1e-4


def test_joint_names_in_any_order_are_mapped(client, joints):
    order = [5, 4, 3, 2, 1, 0]
    target = THREE_POINTS[0][1]
    goal = goal_through([(1.0, [target[i] for i in order])], names=[NAMES[i] for i in order])
    client.send_goal(goal)
    assert client.wait_for_result(rospy.Duration(5))
    assert client.get_result().error_code == R.SUCCESSFUL
    assert np.max(np.abs(position(joints) - target)) < 2e-3


def test_cancel_mid_way_stops_the_arm_and_is_not_successful(client, joints):
    client.send_goal(goal_through(THREE_POINTS))
    time.sleep(1.2)
    t_cancel = time.time()
    client.cancel_goal()
    assert client.wait_for_result(rospy.Duration(5))
    time.sleep(0.5)
    assert client.get_state() != GoalStatus.SUCCEEDED
    assert client.get_result().error_code != R.SUCCESSFUL
    # rest in the arm's time (sample stamps), within 0.3 s of the cancel plus the cancel's way
    # to the node through actionlib on a busy machine (0.5 s): the trajectory had 1.8 s to go
    at_rest = [stamp(m) for _, m in joints.since(t_cancel)
               if stamp(m) >= t_cancel and np.max(np.abs(m.velocity)) < 1e-2]
    assert at_rest and at_rest[0] - t_cancel <= 0.3 + 0.5, at_rest[:1]


def test_an_impossible_path_tolerance_is_path_tolerance_violated(client):
    client.send_goal(goal_through(THREE_POINTS, path_tolerance=1e-6))
    assert client.wait_for_result(rospy.Duration(5))
    assert client.get_result().error_code == R.PATH_TOLERANCE_VIOLATED


@pytest.mark.parametrize("points, reason", [
    # 2 rad in 0.1 s: over the joint speed limit
    ([(0.1, [2.0, 1.4, -1.4, 1.6, 1.6, 0.2])], "rad/s"),
    # a year: sampled every 8 ms it would be 4e9 samples, refused before any planning
    ([(3.2e7, [0.3, 1.4, -1.4, 1.6, 1.6, 0.2])], "600 s"),
], ids=["too fast", "a year long"])
def test_an_impossible_trajectory_is_invalid_goal_before_moving(client, joints, points, reason):
    before = at_rest(joints)
    client.send_goal(goal_through(points))
    assert client.wait_for_result(rospy.Duration(5))
    result = client.get_result()
    assert result.error_code == R.INVALID_GOAL and reason in result.error_string
    assert np.max(np.abs(position(joints) - before)) < 1e-4


def test_refused_in_servo_mode_with_the_reason(client, call):
    assert call("servo_move_enable", ServoMoveEnable, enable=True).ret == 1
    client.send_goal(goal_through(THREE_POINTS))
    assert client.wait_for_result(rospy.Duration(5))
    result = client.get_result()
    assert result.error_code != R.SUCCESSFUL and "servo mode" in result.error_string
