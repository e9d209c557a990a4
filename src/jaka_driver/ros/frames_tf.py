"""TF for the frames the driver owns: the active tool (``flange`` → ``tool_<n>``) and the
active user frame (``base_link`` → ``user_frame_<n>``), so ``tool_position``'s frame_id
exists in the TF tree. robot_state_publisher does the links from ``/joint_states``."""
from __future__ import annotations

import threading

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped

from ..common.transforms import matrix_to_quat
from ..driver import RobotDriver
from ..host import realtime


def transform_stamped(parent: str, child: str, pose, stamp) -> TransformStamped:
    """``pose`` (4×4, m) of ``child`` in ``parent`` as a TF message stamped ``stamp``."""
    t = TransformStamped()
    t.header.stamp = stamp
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = (
        float(v) for v in pose[:3, 3])
    q = matrix_to_quat(pose[:3, :3])
    t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, \
        t.transform.rotation.w = (float(v) for v in q)
    return t


class FrameBroadcaster:
    """Broadcasts the active tool and user frame at ``rate`` Hz from its own thread."""

    def __init__(self, driver: RobotDriver, rate: float = 10.0, prefix: str = ""):
        self._driver = driver
        self._period = 1.0 / rate
        self._prefix = prefix
        self._tf = tf2_ros.TransformBroadcaster()
        threading.Thread(target=self._run, name="frame-tf", daemon=True).start()

    @realtime.runs_periodically
    def _run(self) -> None:
        while not rospy.is_shutdown():
            try:
                st = self._driver.state()
                tool, user = self._driver.frames()
                stamp = rospy.Time.now()
                p = self._prefix
                out = [transform_stamped(f"{p}flange", f"{p}tool_{st.tool_id}", tool, stamp)]
                if st.user_id:
                    out.append(transform_stamped(f"{p}base_link", f"{p}user_frame_{st.user_id}",
                                                 user, stamp))
                self._tf.sendTransform(out)
            except Exception as exc:  # noqa: BLE001 — TF must not take the node down
                rospy.logerr_throttle(10.0, f"frame TF failed: {exc!r}")
            try:
                rospy.sleep(self._period)
            except rospy.ROSInterruptException:
                return          # shutting down (in sim time the sleep is interrupted, not ended)
