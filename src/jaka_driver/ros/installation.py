"""The arm's mounting on ROS: ``~set_installation_angle`` (``jaka_driver_msgs/
SetInstallationAngle``: tilt_x, rot_z rad → ret, message) and ``~get_installation_angle``
(``jaka_driver_msgs/GetInstallationAngle``: → quaternion (x, y, z, w), rpy rad, ret, message),
through RobotDriver only; and the ``~installation_angle`` parameter (``[tilt_x, rot_z]`` rad, as
the launch argument passes it) applied once at start-up.

``robot_description`` carries the launch's mounting as its ``world → base_link`` joint
(``scripts/robot_description --installation-angle``), which robot_state_publisher publishes: a mounting set later by the
service turns the arm's gravity but not that frame, and the answer says so; an arm that reports
another mounting than the launch's at start-up is logged as a warning."""
from __future__ import annotations

import numpy as np
import rospy

from jaka_driver_msgs.srv import (GetInstallationAngle, GetInstallationAngleResponse,
                                  SetInstallationAngle, SetInstallationAngleResponse)

from ..common.installation import Installation, installation
from ..common.results import Code
from ..driver import RobotDriver


def advertise_installation(driver: RobotDriver) -> None:
    def set_angle(req) -> SetInstallationAngleResponse:
        result = driver.set_installation_angle(req.tilt_x, req.rot_z)
        if not result.ok:
            rospy.logwarn("set_installation_angle refused (%d): %s", result.code, result.message)
            return SetInstallationAngleResponse(ret=int(result.code), message=result.message)
        message = (f"{result.message} (robot_description and TF keep the launch's mounting: "
                   f"launch with installation_angle:=\"[{req.tilt_x:g}, {req.rot_z:g}]\" to "
                   "show it)")
        rospy.loginfo(message)
        return SetInstallationAngleResponse(ret=int(result.code), message=message)

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
    """``~installation_angle`` (``[tilt_x, rot_z]`` rad, or ``none`` / "" / [] for upright as the
    arm is — the launch file's default is a word, since roslaunch lists an empty default as a
    required argument):
    set it; a value out of range is a message for a fatal log (else None) — an arm that cannot
    take it now (a controller not reached yet) is a warning, the node runs on. Then the arm's own mounting is
    compared with the launch's (what ``robot_description`` shows)."""
    shown = Installation()
    if value not in ("", None, [], "none"):
        try:
            tilt_x, rot_z = (float(v) for v in value)
        except (TypeError, ValueError):
            return f"~installation_angle is {value!r}; expected [tilt_x, rot_z] in rad"
        result = driver.set_installation_angle(tilt_x, rot_z)
        if result.code == Code.INVALID_PARAMETER:
            return f"~installation_angle: {result.message}"
        if not result.ok:      # a controller not reached (yet), or refusing: the node runs on
            rospy.logwarn(f"~installation_angle not set ({result.code}): {result.message}; "
                          "call set_installation_angle once the arm can take it")
            return None
        rospy.loginfo(result.message)
        shown = installation(tilt_x, rot_z)          # what scripts/robot_description put there
    held = result_value(driver)
    if held is not None and not np.allclose(held.rotation, shown.rotation, atol=1e-3):
        rospy.logwarn(f"the arm reports it is mounted {held.describe()}, but robot_description "
                      f"shows it {shown.describe()}: launch with installation_angle:="
                      f"\"[{held.tilt_x:.4f}, {held.rot_z:.4f}]\"")
    return None


def result_value(driver: RobotDriver):
    """The arm's mounting as it reports it, or None (a backend that cannot say)."""
    result = driver.installation_angle()
    return result.value if result.ok else None
