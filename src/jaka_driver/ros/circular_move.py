"""``~circular_move`` (``jaka_driver_msgs/CircularMove``): an arc from where the TCP stands
through ``pose_mid`` to ``pose_end``, read as ``linear_move`` reads its pose (mm + rotation
vector, or RPY with ``~conventions:=jaka_code``), through RobotDriver.circular_move
(docs/interface.md, "circular_move")."""
from __future__ import annotations

import rospy

from jaka_driver_msgs.srv import CircularMove, CircularMoveResponse

from ..driver import RobotDriver
from .service_answers import answer_with as _ret, logged as _logged


def advertise_circular_move(driver: RobotDriver) -> rospy.Service:
    answer = _ret(CircularMoveResponse)
    return rospy.Service("~circular_move", CircularMove, _logged("circular_move", lambda r: answer(
        driver.circular_move(r.pose_mid, r.pose_end, r.mvvelo, r.mvacc, r.turns,
                             r.attitude_mode, r.coord_mode))))
