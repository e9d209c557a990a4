"""``~on_limit`` (``std_msgs/Bool``, latched): whether a joint is on its soft position limit —
a controller's ``on_soft_limit`` from every status packet, the twin's within 0.1° of a limit —
published with the state topics' samples whenever it changes (and once at start)."""
from __future__ import annotations

import rospy
from std_msgs.msg import Bool

from ..backend.robot_state import RobotState


class OnLimitTopic:
    """Offered each sample by the state publisher (``also_publish``)."""

    def __init__(self, also_publish: list):
        self._pub = rospy.Publisher("~on_limit", Bool, queue_size=1, latch=True)
        self._last = None
        also_publish.append(self.publish_sample)

    def publish_sample(self, st: RobotState) -> None:
        if st.on_limit != self._last:
            self._last = st.on_limit
            self._pub.publish(Bool(st.on_limit))
