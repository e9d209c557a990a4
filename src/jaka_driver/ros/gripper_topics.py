"""The gripper's topics (docs/interface.md, "Gripper"), from ``driver.gripper`` only:

- ``~gripper/state`` (jaka_driver_msgs/GripperState, latched): powered, initialised, opening
  (m and ‰), grip state, object held, force and speed settings — published at start and on
  every change, looked at 10 times a second (the status signals are polled at most at 10 Hz);
- the finger joints ``gripper_finger_left`` / ``_right`` (m each, half the opening) on
  ``joint_states`` with every sample of the arm, from the state publisher's thread, so
  robot_state_publisher places the fingers in TF at the arm's rate.
"""
from __future__ import annotations

import threading
import time

import rospy
from sensor_msgs.msg import JointState

from jaka_driver_msgs.msg import GripperState as GripperStateMsg

from ..backend.robot_state import RobotState
from ..driver import RobotDriver

FINGER_JOINTS = ("gripper_finger_left", "gripper_finger_right")
STATE_CHECK_PERIOD = 0.1        # s (wall) between looks for a change


def state_message(driver: RobotDriver) -> GripperStateMsg:
    gripper = driver.gripper
    state = gripper.state()
    device = gripper.device
    return GripperStateMsg(
        model=gripper.kind, powered=bool(gripper.powered), initialised=state.initialised,
        position=float(state.opening), position_permille=int(state.position),
        grip_state=-1 if state.grip_state is None else int(state.grip_state),
        object_held=state.object_held, force_percent=int(device.force_pct),
        speed_percent=int(device.speed_pct))


class GripperTopics:
    """``~gripper/state`` and the finger joints (see the module); ``also_publish`` is the state
    publisher's list of per-sample publishers."""

    def __init__(self, driver: RobotDriver, also_publish: list):
        self.driver = driver
        self._state = rospy.Publisher("~gripper/state", GripperStateMsg, queue_size=1,
                                      latch=True)
        self._joints = rospy.Publisher("joint_states", JointState, queue_size=None)
        self._fingers = JointState(name=list(FINGER_JOINTS), position=[0.0, 0.0])
        self._last = None
        also_publish.append(self._publish_fingers)
        threading.Thread(target=self._watch, name="gripper-state", daemon=True).start()

    def _publish_fingers(self, st: RobotState) -> None:
        half = float(self.driver.gripper.state().opening) / 2.0
        msg = self._fingers
        msg.header.stamp = rospy.Time.from_sec(st.stamp)
        msg.position = [half, half]
        self._joints.publish(msg)

    def _watch(self) -> None:
        while not rospy.is_shutdown():
            try:
                msg = state_message(self.driver)
                key = (msg.powered, msg.initialised, msg.position_permille, msg.grip_state,
                       msg.force_percent, msg.speed_percent)
                if key != self._last:
                    msg.stamp = rospy.Time.from_sec(self.driver.state().stamp)
                    self._state.publish(msg)
                    self._last = key
            except Exception as exc:  # noqa: BLE001 — the topic must outlive a bad read
                rospy.logerr_throttle(5.0, f"gripper state failed: {exc!r}")
            time.sleep(STATE_CHECK_PERIOD)
