"""The arm's mounting on ROS: ``~set_installation_angle`` (``jaka_driver_msgs/
SetInstallationAngle``: tilt_x, rot_z rad → ret, message) and ``~get_installation_angle``
(``jaka_driver_msgs/GetInstallationAngle``: → quaternion (x, y, z, w), rpy rad, ret, message),
through RobotDriver only; and the ``~installation_angle`` parameter (``[tilt_x, rot_z]`` rad, as
the launch argument passes it) applied once at start-up."""
from __future__ import annotations

import rospy

from jaka_driver_msgs.srv import (GetInstallationAngle, GetInstallationAngleResponse,
                                  SetInstallationAngle, SetInstallationAngleResponse)

from ..driver import RobotDriver


def advertise_installation(driver: RobotDriver) -> None:
    def set_angle(req) -> SetInstallationAngleResponse:
        result = driver.set_installation_angle(req.tilt_x, req.rot_z)
        if not result.ok:
            rospy.logwarn("set_installation_angle refused (%d): %s", result.code, result.message)
        return SetInstallationAngleResponse(ret=int(result.code), message=result.message)

    def get_angle(_req) -> GetInstallationAngleResponse:
        result = driver.installation_angle()
        if not result.ok:
            return GetInstallationAngleResponse(ret=int(result.code), message=result.message)
        mounting = result.value
        return GetInstallationAngleResponse(quaternion=[float(v) for v in mounting.quaternion],
                                            rpy=[float(v) for v in mounting.rpy],
                                            ret=int(result.code), message=result.message)

    rospy.Service("~set_installation_angle", SetInstallationAngle, set_angle)
    rospy.Service("~get_installation_angle", GetInstallationAngle, get_angle)


def apply_parameter(driver: RobotDriver, value) -> str | None:
    """``~installation_angle`` (``[tilt_x, rot_z]`` rad, or "" / [] for upright as the arm is):
    set it; why not (a message for a fatal log), or None."""
    if value in ("", None, []):
        return None
    try:
        tilt_x, rot_z = (float(v) for v in value)
    except (TypeError, ValueError):
        return f"~installation_angle is {value!r}; expected [tilt_x, rot_z] in rad"
    result = driver.set_installation_angle(tilt_x, rot_z)
    if not result.ok:
        return f"~installation_angle: {result.message}"
    rospy.loginfo(result.message)
    return None
