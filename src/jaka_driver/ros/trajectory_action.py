"""FollowJointTrajectory for MoveIt, with joint_trajectory_controller's semantics.

Goals are checked whole before anything moves (joint names in any order, times increasing,
positions/velocities within limits, first point close to the arm, the interpolated path within
the speed limits); the waypoints are interpolated in time (quintic / cubic / linear per segment)
and sampled every 8 ms into a trajectory the backend plays; feedback (desired / actual / error)
goes out at 50 Hz; path and goal tolerances are enforced; cancel or a new goal stops the arm;
SUCCESSFUL only when the arm is at the goal.
"""
from __future__ import annotations

import threading

import actionlib
import numpy as np
import rospy
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryFeedback,
                              FollowJointTrajectoryResult)
from trajectory_msgs.msg import JointTrajectoryPoint

from ..common.constants import SERVO_CYCLE
from ..driver import RobotDriver
from ..motion.spline import Waypoint, sample_waypoints
from ..motion.trajectory import MAX_MOTION_DURATION, JointTrajectory

START_TOLERANCE = 0.05      # rad: a point at t = 0 must be this close to the arm
Result = FollowJointTrajectoryResult


class GoalRejected(Exception):
    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code


class TrajectoryActionServer:
    """``control_msgs/FollowJointTrajectoryAction`` on ``name`` (default
    ``~follow_joint_trajectory``)."""

    def __init__(self, driver: RobotDriver, name: str = "~follow_joint_trajectory"):
        self.driver = driver
        self.model = driver.model
        self._server = actionlib.SimpleActionServer(rospy.resolve_name(name),
                                                    FollowJointTrajectoryAction,
                                                    execute_cb=self._execute, auto_start=False)
        self._lock = threading.Lock()
        self._server.start()

    # ---- goal checks -------------------------------------------------------------------------
    def _plan(self, goal) -> tuple[JointTrajectory, np.ndarray, np.ndarray, float]:
        """The sampled trajectory, per-joint path and goal tolerances (model order; 0 = none),
        and the goal time tolerance; raises GoalRejected."""
        traj = goal.trajectory
        names = list(traj.joint_names)
        model_names = list(self.model.joint_names)
        if sorted(names) != sorted(model_names) or len(set(names)) != len(names):
            raise GoalRejected(Result.INVALID_JOINTS, f"joint_names {names} must be exactly "
                               f"{model_names} (any order)")
        order = [names.index(n) for n in model_names]
        if not traj.points:
            raise GoalRejected(Result.INVALID_GOAL, "the trajectory has no points")
        state = self.driver.state()
        waypoints, previous = [], -1.0
        for i, p in enumerate(traj.points):
            t = p.time_from_start.to_sec()
            if t <= previous or (t == 0.0 and i > 0):
                raise GoalRejected(Result.INVALID_GOAL, f"point {i}: time_from_start {t:.3f} s "
                                   f"is not after the previous point's {previous:.3f} s")
            previous = t
            if t > MAX_MOTION_DURATION:
                raise GoalRejected(Result.INVALID_GOAL, f"point {i}: time_from_start {t:.4g} s "
                                   f"is above the limit of {MAX_MOTION_DURATION:g} s for one "
                                   "trajectory (split it)")
            q = self._vector(p.positions, f"point {i} positions", order, required=True)
            qd = self._vector(p.velocities, f"point {i} velocities", order)
            qdd = self._vector(p.accelerations, f"point {i} accelerations", order)
            for j, name in enumerate(model_names):
                if not self.model.lower[j] <= q[j] <= self.model.upper[j]:
                    raise GoalRejected(Result.INVALID_GOAL, f"point {i}: {name} {q[j]:.4f} rad is "
                                       f"outside [{self.model.lower[j]:.2f}, "
                                       f"{self.model.upper[j]:.2f}]")
                if qd is not None and abs(qd[j]) > self.model.max_velocity[j]:
                    raise GoalRejected(Result.INVALID_GOAL, f"point {i}: {name} velocity "
                                       f"{qd[j]:.3f} rad/s exceeds {self.model.max_velocity[j]:.2f}")
            if t == 0.0:
                gap = np.max(np.abs(q - state.joint_position))
                if gap > START_TOLERANCE:
                    raise GoalRejected(Result.INVALID_GOAL, f"the point at t = 0 is {gap:.3f} rad "
                                       f"from the arm (tolerance {START_TOLERANCE} rad)")
            waypoints.append(Waypoint(t, q, qd, qdd))
        times, q, qd = sample_waypoints(state.joint_position, waypoints, SERVO_CYCLE)
        ratio = np.max(np.abs(qd), axis=0) / self.model.max_velocity
        worst = int(np.argmax(ratio))
        if ratio[worst] > 1.0 + 1e-6:
            raise GoalRejected(Result.INVALID_GOAL, f"the interpolated trajectory needs "
                               f"{model_names[worst]} at {ratio[worst] * self.model.max_velocity[worst]:.2f}"
                               f" rad/s, limit {self.model.max_velocity[worst]:.2f} rad/s")
        path_tol = self._tolerances(goal.path_tolerance, model_names)
        goal_tol = self._tolerances(goal.goal_tolerance, model_names)
        return (JointTrajectory(times=times, q=q, qd=qd), path_tol, goal_tol,
                goal.goal_time_tolerance.to_sec())

    @staticmethod
    def _vector(values, what, order, required=False):
        if len(values) == 0 and not required:
            return None
        if len(values) != len(order):
            raise GoalRejected(Result.INVALID_GOAL, f"{what} has {len(values)} values, expected "
                               f"{len(order)}")
        v = np.asarray(values, float)[order]
        if not np.all(np.isfinite(v)):
            raise GoalRejected(Result.INVALID_GOAL, f"{what} contains NaN or inf")
        return v

    @staticmethod
    def _tolerances(tolerances, names) -> np.ndarray:
        out = np.zeros(len(names))
        for tol in tolerances:
            if tol.name in names and tol.position > 0:
                out[names.index(tol.name)] = tol.position
        return out

    # ---- execution ---------------------------------------------------------------------------------
    def _execute(self, goal) -> None:
        try:
            trajectory, path_tol, goal_tol, goal_time = self._plan(goal)
        except GoalRejected as rejected:
            rospy.logwarn(f"trajectory rejected: {rejected}")
            self._server.set_aborted(Result(error_code=rejected.code, error_string=str(rejected)),
                                     str(rejected))
            return
        stamp = goal.trajectory.header.stamp
        start_at = None
        if not stamp.is_zero():
            if (stamp.to_sec() + trajectory.duration) < rospy.Time.now().to_sec():
                message = "the trajectory ends before now (header.stamp in the past)"
                self._server.set_aborted(Result(error_code=Result.OLD_HEADER_TIMESTAMP,
                                                error_string=message), message)
                return
            # waited for on the driver's clock inside the request, not with rospy.sleep here:
            # in sim time the start lands in the cycle the stamp names, not when this thread
            # wakes up after /clock has passed it
            start_at = stamp.to_sec()

        verdict = {"code": Result.PATH_TOLERANCE_VIOLATED}
        names = list(self.model.joint_names)

        def monitor(t, state):
            desired_q, desired_qd = trajectory.sample(t)
            error = desired_q - state.joint_position
            self._feedback(names, desired_q, desired_qd, state, error)
            if self._server.is_preempt_requested():
                verdict["code"] = Result.GOAL_TOLERANCE_VIOLATED
                verdict["preempted"] = True
                return "cancelled before the goal was reached"
            if state.in_error or state.emergency_stop or not state.enabled:
                verdict["code"] = Result.PATH_TOLERANCE_VIOLATED
                return f"aborted: {state.error_message or 'robot stopped'}"
            violated = (path_tol > 0) & (np.abs(error) > path_tol)
            if t <= trajectory.duration and violated.any():
                j = int(np.argmax(violated))
                verdict["code"] = Result.PATH_TOLERANCE_VIOLATED
                return (f"path tolerance violated: {names[j]} error {error[j]:.4f} rad > "
                        f"{path_tol[j]:.4f} rad at t = {t:.2f} s")
            if goal_time > 0 and t > trajectory.duration + goal_time:
                final_error = trajectory.q[-1] - state.joint_position
                missed = (goal_tol > 0) & (np.abs(final_error) > goal_tol)
                if missed.any():
                    j = int(np.argmax(missed))
                    verdict["code"] = Result.GOAL_TOLERANCE_VIOLATED
                    return (f"goal tolerance violated: {names[j]} error {final_error[j]:.4f} rad "
                            f"> {goal_tol[j]:.4f} rad {goal_time:.2f} s after the end")
            return None

        with self._lock:
            outcome = self.driver.follow_trajectory(trajectory, monitor, start_at=start_at)
        if outcome.ok:
            self._server.set_succeeded(Result(error_code=Result.SUCCESSFUL,
                                              error_string=outcome.message), outcome.message)
        elif verdict.get("preempted"):
            self._server.set_preempted(Result(error_code=verdict["code"],
                                              error_string=outcome.message), outcome.message)
        else:
            rospy.logwarn(f"trajectory aborted: {outcome.message}")
            code = verdict["code"] if outcome.code == -12 else Result.INVALID_GOAL
            self._server.set_aborted(Result(error_code=code, error_string=outcome.message),
                                     outcome.message)

    def _feedback(self, names, q, qd, state, error) -> None:
        fb = FollowJointTrajectoryFeedback()
        fb.header.stamp = rospy.Time.from_sec(state.stamp)
        fb.joint_names = names
        fb.desired = JointTrajectoryPoint(positions=q.tolist(), velocities=qd.tolist())
        fb.actual = JointTrajectoryPoint(positions=state.joint_position.tolist(),
                                         velocities=state.joint_velocity.tolist())
        fb.error = JointTrajectoryPoint(positions=error.tolist(),
                                        velocities=(qd - state.joint_velocity).tolist())
        self._server.publish_feedback(fb)
