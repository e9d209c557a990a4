"""``~set_servo_filter`` (``jaka_driver_msgs/SetServoFilter``): the filter servo targets pass
through from the next servo mode on — JAKA's six, with the parameters of the chosen one
(docs/interface.md, "set_servo_filter"), through RobotDriver.set_servo_filter. The active
filter is in ``/diagnostics`` (the backend's description)."""
from __future__ import annotations

import rospy

from jaka_driver_msgs.srv import SetServoFilter, SetServoFilterResponse

from ..driver import RobotDriver
from .service_answers import answer_with as _ret, logged as _logged


def advertise_servo_filter(driver: RobotDriver) -> rospy.Service:
    answer = _ret(SetServoFilterResponse)

    def serve(r):
        return answer(driver.set_servo_filter(
            r.filter_type, lpf_cutoff_hz=r.lpf_cutoff_hz, nlf_max_vr=r.nlf_max_vr,
            nlf_max_ar=r.nlf_max_ar, nlf_max_jr=r.nlf_max_jr, nlf_max_vp=r.nlf_max_vp,
            nlf_max_ap=r.nlf_max_ap, nlf_max_jp=r.nlf_max_jp, mmf_buffer=r.mmf_buffer,
            mmf_kp=r.mmf_kp, mmf_kv=r.mmf_kv, mmf_ka=r.mmf_ka))
    return rospy.Service("~set_servo_filter", SetServoFilter, _logged("set_servo_filter", serve))
