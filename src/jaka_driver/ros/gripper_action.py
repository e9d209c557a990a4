"""The gripper on the tool connector for MoveIt and users (docs/interface.md, "Gripper"),
calling ``driver.gripper`` only:

- ``~gripper/gripper_action`` (control_msgs/GripperCommand; the name is ``~gripper_action``):
  ``command.position`` is the opening between the pads in m, ``command.max_effort`` the force
  per jaw in N (0: the force setting as it is). Feedback and result carry ``position`` (m),
  ``effort`` (N, the force setting), ``stalled`` (grip state 2: stopped on an object) and
  ``reached_goal`` (grip state 1: at the position, nothing between the fingers), as MoveIt's
  gripper controller and the Robotiq / DH action servers read them. A goal is aborted at once,
  with the reason, while the gripper is not powered or not initialised (the door's refusal);
  the next goal preempts the one running. A goal ends when the polled grip state is no longer
  "moving" — not before two polls of the status signals after the command (the state read
  before might be the last goal's) — succeeded when stalled or reached, aborted when the
  object dropped (3) or the move outlasted its stroke time at the set speed plus 2 s.
- ``~gripper/initialise`` (jaka_driver_msgs/InitGripper), ``~gripper/set_force`` and
  ``~gripper/set_speed`` (jaka_driver_msgs/SetGripperPercent): ``ret`` 1 or the door's
  refusal.

Both are served on every node: without a gripper every request is refused (-9, saying how to
mount one) and every goal aborted with that reason.

Times run on the driver's clock (sim time on a twin in sim time).
"""
from __future__ import annotations

import actionlib
import rospy
from control_msgs.msg import GripperCommandAction, GripperCommandFeedback, GripperCommandResult

from jaka_driver_msgs.srv import InitGripper, InitGripperResponse, SetGripperPercent, \
    SetGripperPercentResponse

from ..devices import GripperState, GripState
from ..driver import RobotDriver

POLL = 0.02                 # s between looks at the polled state
SETTLE_POLLS = 2            # polls of the status signals a goal waits for before it may end
SLACK = 2.0                 # s beyond the stroke time at the set speed before a goal is aborted


class GripperActionServer:
    """``control_msgs/GripperCommandAction`` on ``name`` (see the module)."""

    def __init__(self, driver: RobotDriver, name: str = "~gripper/gripper_action",
                 poll_frequency: float = 10.0):
        self.driver = driver
        self._settle = SETTLE_POLLS / poll_frequency
        self._server = actionlib.SimpleActionServer(rospy.resolve_name(name),
                                                    GripperCommandAction,
                                                    execute_cb=self._execute, auto_start=False)
        self._server.start()

    def _effort(self) -> float:
        """N per jaw at the force setting (0 without a gripper)."""
        if self.driver.gripper.absent is not None:
            return 0.0
        device = self.driver.gripper.device
        return float(device.figures.force(device.force_pct, device.registers.force_range))

    def _fill(self, msg, state: GripperState, goal: float):
        msg.position = float(state.opening)
        msg.effort = self._effort()
        msg.stalled = state.grip_state == GripState.CAUGHT
        msg.reached_goal = state.grip_state == GripState.REACHED
        return msg

    def _execute(self, goal) -> None:
        gripper, clock = self.driver.gripper, self.driver.clock
        target, effort = float(goal.command.position), float(goal.command.max_effort)
        answer = gripper.move(target, effort)
        if not answer.ok:
            self._server.set_aborted(self._fill(GripperCommandResult(), gripper.state(), target),
                                     f"refused ({answer.code}): {answer.message}")
            return
        device = gripper.device
        start = clock.now()
        deadline = start + device.figures.stroke_time * 100.0 / device.speed_pct + SLACK
        while not rospy.is_shutdown():
            if self._server.is_preempt_requested():
                self._server.set_preempted(self._fill(GripperCommandResult(), gripper.state(),
                                                      target), "preempted by a new goal")
                return
            clock.sleep(POLL)
            state = gripper.state()
            self._server.publish_feedback(self._fill(GripperCommandFeedback(), state, target))
            if clock.now() - start < self._settle or state.grip_state == GripState.MOVING:
                if clock.now() > deadline:
                    self._server.set_aborted(self._fill(GripperCommandResult(), state, target),
                                             f"the gripper still moves after "
                                             f"{clock.now() - start:.1f} s")
                    return
                continue
            result = self._fill(GripperCommandResult(), state, target)
            if result.stalled or result.reached_goal:
                self._server.set_succeeded(result, f"grip state {int(state.grip_state)} at "
                                           f"{state.opening * 1000:.1f} mm")
            else:
                self._server.set_aborted(result, f"grip state {state.grip_state!r}: the object "
                                         "dropped" if state.grip_state == GripState.DROPPED
                                         else "no answer from the gripper")
            return


def advertise_gripper_services(driver: RobotDriver) -> list:
    """``~gripper/initialise``, ``~gripper/set_force``, ``~gripper/set_speed``."""
    gripper = driver.gripper

    def initialise(req):
        r = gripper.initialise(bool(req.full_calibration))
        return InitGripperResponse(ret=int(r.code), message=r.message)

    def percent(request):
        def handle(req):
            r = request(req.percent)
            return SetGripperPercentResponse(ret=int(r.code), message=r.message)
        return handle

    return [rospy.Service("~gripper/initialise", InitGripper, initialise),
            rospy.Service("~gripper/set_force", SetGripperPercent, percent(gripper.set_force)),
            rospy.Service("~gripper/set_speed", SetGripperPercent, percent(gripper.set_speed))]
