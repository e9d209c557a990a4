"""The twin's parts (docs/interface.md, "Twin"), from ``driver.twin.parts()`` only: every 5th
sample of the arm (25 Hz; in sim time at the same sim times, run after run), each part's pose
in the base frame as a TF frame named after the part (``base_link`` → ``box``) and the same
transforms on ``~sim/parts`` (tf2_msgs/TFMessage), so a test can read what the gripper did.
Silent when the scene has no parts, and on a controller."""
from __future__ import annotations

import rospy
import tf2_ros
from tf2_msgs.msg import TFMessage

from ..backend.robot_state import RobotState
from ..driver import RobotDriver
from .frames_tf import transform_stamped

EVERY = 5                 # samples between two publications (40 ms)


class PartsPublisher:
    """See the module; ``also_publish`` is the state publisher's list of per-sample
    publishers, ``prefix`` the TF prefix."""

    def __init__(self, driver: RobotDriver, also_publish: list, prefix: str = ""):
        self._driver = driver
        self._prefix = prefix
        self._topic = rospy.Publisher("~sim/parts", TFMessage, queue_size=1)
        self._tf = tf2_ros.TransformBroadcaster()
        self._count = 0
        also_publish.append(self._publish)

    def _publish(self, st: RobotState) -> None:
        self._count += 1
        if self._count % EVERY:
            return
        parts = self._driver.twin.parts()
        if not parts:
            return
        stamp = rospy.Time.from_sec(st.stamp)
        p = self._prefix
        transforms = [transform_stamped(f"{p}base_link", f"{p}{name}", pose, stamp)
                      for name, pose in parts.items()]
        self._topic.publish(TFMessage(transforms=transforms))
        self._tf.sendTransform(transforms)
