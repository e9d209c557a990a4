"""The FollowJointTrajectory action on the zu5 twin, with actionlib's SimpleActionClient: a
3-point trajectory succeeds and the measured path follows the interpolated reference; wrong
joints are INVALID_JOINTS; a cancel stops the arm and is not SUCCESSFUL; an impossible path
tolerance is PATH_TOLERANCE_VIOLATED; servo mode refuses the goal.

The twin owns time (sim_time) and stands still unless a test steps it; each test starts from
~sim/reset at START. The samples are stamped in sim time, one per cycle, none skipped: on the
wall clock a twin that stalls on a busy machine skips its stamps ahead while the trajectory
goes on cycle by cycle, and the path seemed 0.28 rad off its reference."""
import actionlib
import numpy as np
import pytest
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal,
                              FollowJointTrajectoryResult, JointTolerance)
from trajectory_msgs.msg import JointTrajectoryPoint

from support.ros_harness import (CYCLE, START, action_done, pause_twin, reset_twin, sample_at,
                                 start_sim_time_driver, stamp, step_twin, step_twin_to,
                                 wait_until)
from jaka_msgs.srv import ServoMoveEnable

from jaka_driver.motion.spline import Waypoint, sample_waypoints

pytestmark = pytest.mark.ros

NAMES = [f"joint_{i}" for i in range(1, 7)]
R = FollowJointTrajectoryResult
#: s of wall time the node is given to answer what needs no cycle of the twin
ANSWER = 30.0
DONE = (GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.PREEMPTED, GoalStatus.REJECTED,
        GoalStatus.RECALLED, GoalStatus.LOST)


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):
    return start_sim_time_driver(request)


@pytest.fixture(scope="module")
def client(sim_driver, rospy_node):
    c = actionlib.SimpleActionClient(sim_driver.name("follow_joint_trajectory"),
                                     FollowJointTrajectoryAction)
    # 10 s of wall time, asked in short waits: the twin's sim time, which rospy counts here,
    # runs many times faster than the wall clock until the module pauses it
    assert wait_until(lambda: c.wait_for_server(rospy.Duration(0.05)), 10.0)
    return c


@pytest.fixture(scope="module", autouse=True)
def paused(client, call):
    """The module's twin stands still between the steps its tests make."""
    pause_twin(call)
    yield
    pause_twin(call, False)


@pytest.fixture(autouse=True)
def at_start(call) -> float:
    """The arm at rest at START: the sim time (s) of its first sample there."""
    assert call("servo_move_enable", ServoMoveEnable, enable=False).ret == 1
    return reset_twin(call, START)


def goal_through(points, names=NAMES, path_tolerance=None):
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = names
    for t, q in points:
        goal.trajectory.points.append(JointTrajectoryPoint(
            positions=q, velocities=[0.0] * 6, time_from_start=rospy.Duration(t)))
    if path_tolerance is not None:
        goal.path_tolerance = [JointTolerance(name=n, position=path_tolerance) for n in NAMES]
    return goal


def started(client, call, goal) -> float:
    """Send ``goal`` and step the twin one cycle at a time until its first feedback (the
    trajectory runs): the feedback's stamp (sim s)."""
    feedback = []
    client.send_goal(goal, feedback_cb=lambda fb: feedback.append(fb.header.stamp.to_sec()))
    for _ in range(1000):
        step_twin(call, 1)
        if wait_until(lambda: feedback, 0.2):
            return feedback[0]
    raise AssertionError("no feedback in 1000 cycles")


def finished(client, call, chunk: int = 25, limit: float = 20.0) -> float:
    """Step the twin ``chunk`` cycles at a time until the goal is done (at most ``limit`` s of
    sim time): the sim time (s) of the last step."""
    for _ in range(int(limit / (chunk * CYCLE))):
        t = step_twin(call, chunk)
        if client.simple_state == actionlib.SimpleGoalState.DONE:     # the result is in
            return t
    raise AssertionError(f"the goal was not done after {limit} s of sim time")


def answered(client) -> None:
    """A goal refused before anything moves is answered without a cycle of the twin (read on
    the wall clock, from the goal's own handle: support.ros_harness.action_done)."""
    assert action_done(client, ANSWER)


def still_at(joints, call, q, after: float) -> None:
    """No sample from ``after`` to 0.2 s of sim time later has left ``q`` (rad) by 1e-4 rad."""
    end = step_twin(call, 25)
    sample_at(joints, end)
    with joints._lock:
        moved = [np.max(np.abs(np.array(m.position) - q)) for _, m in joints.samples
                 if after <= stamp(m) <= end + 1e-6]
    assert len(moved) >= 25 and max(moved) < 1e-4, max(moved)


THREE_POINTS = [(1.0, [0.3, 1.4, -1.4, 1.6, 1.6, 0.2]),
                (2.0, [0.6, 1.3, -1.2, 1.7, 1.5, 0.4]),
                (3.0, [0.4, 1.5, -1.3, 1.5, 1.7, 0.1])]


def test_three_points_succeed_and_the_path_stays_within_1e2_rad(client, call, joints, at_start):
    client.send_goal(goal_through(THREE_POINTS))
    end = finished(client, call)
    assert client.get_state() == GoalStatus.SUCCEEDED
    assert client.get_result().error_code == R.SUCCESSFUL
    last = sample_at(joints, end)
    with joints._lock:
        samples = [m for _, m in joints.samples if at_start <= stamp(m) <= end + 1e-6]
    stamps = np.array([stamp(m) for m in samples])
    q = np.array([m.position for m in samples])
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
    assert np.max(np.abs(np.array(last.position) - THREE_POINTS[-1][1])) < 2e-3


def test_wrong_joint_names_are_invalid_joints(client, call, joints, at_start):
    client.send_goal(goal_through(THREE_POINTS, names=NAMES[:5] + ["wrist_3"]))
    answered(client)
    assert client.get_result().error_code == R.INVALID_JOINTS
    still_at(joints, call, START, at_start)


def test_joint_names_in_any_order_are_mapped(client, call, joints):
    order = [5, 4, 3, 2, 1, 0]
    target = THREE_POINTS[0][1]
    goal = goal_through([(1.0, [target[i] for i in order])], names=[NAMES[i] for i in order])
    client.send_goal(goal)
    end = finished(client, call)
    assert client.get_result().error_code == R.SUCCESSFUL
    assert np.max(np.abs(np.array(sample_at(joints, end).position) - target)) < 2e-3


def test_cancel_mid_way_stops_the_arm_and_is_not_successful(client, call, joints):
    begun = started(client, call, goal_through(THREE_POINTS))
    t_cancel = step_twin_to(call, begun + 1.2)
    client.cancel_goal()
    # the cancel acts at the sim time it arrived: the twin stands still until it is in
    assert wait_until(lambda: client.gh.get_goal_status() in (GoalStatus.PREEMPTING,) + DONE,
                      ANSWER)
    end = finished(client, call)
    assert client.get_state() != GoalStatus.SUCCEEDED
    assert client.get_result().error_code != R.SUCCESSFUL
    # at rest (sample stamps) within 0.3 s of the cancel: the trajectory had 1.8 s to go
    sample_at(joints, end)
    with joints._lock:
        at_rest = [stamp(m) for _, m in joints.samples
                   if stamp(m) >= t_cancel and np.max(np.abs(m.velocity)) < 1e-2]
    assert at_rest and at_rest[0] - t_cancel <= 0.3, at_rest[:1]


def test_an_impossible_path_tolerance_is_path_tolerance_violated(client, call):
    client.send_goal(goal_through(THREE_POINTS, path_tolerance=1e-6))
    finished(client, call)
    assert client.get_result().error_code == R.PATH_TOLERANCE_VIOLATED


@pytest.mark.parametrize("points, reason", [
    # 2 rad in 0.1 s: over the joint speed limit
    ([(0.1, [2.0, 1.4, -1.4, 1.6, 1.6, 0.2])], "rad/s"),
    # a year: sampled every 8 ms it would be 4e9 samples, refused before any planning
    ([(3.2e7, [0.3, 1.4, -1.4, 1.6, 1.6, 0.2])], "600 s"),
], ids=["too fast", "a year long"])
def test_an_impossible_trajectory_is_invalid_goal_before_moving(client, call, joints, at_start,
                                                                 points, reason):
    client.send_goal(goal_through(points))
    answered(client)
    result = client.get_result()
    assert result.error_code == R.INVALID_GOAL and reason in result.error_string
    still_at(joints, call, START, at_start)


def test_refused_in_servo_mode_with_the_reason(client, call):
    assert call("servo_move_enable", ServoMoveEnable, enable=True).ret == 1
    client.send_goal(goal_through(THREE_POINTS))
    answered(client)
    result = client.get_result()
    assert result.error_code != R.SUCCESSFUL and "servo mode" in result.error_string
