"""The flange force/torque sensor and force control on ROS (docs/interface.md, "Force"):
request message → ``driver.force`` (RobotDriver's door, :mod:`jaka_driver.driver.
force_requests`) → response, on every backend (an arm without a sensor answers -9 and says
how to mount one).

Names, as ROS users of other arms know them: ``zero_ftsensor`` (std_srvs/Trigger) is the UR
driver's; ``ft_sensor_enable`` (SetBool) and ``get_ft_sensor_data`` xArm's; the topic
``wrench`` the UR driver's. The rest name JAKA's SDK functions: ``set_admittance`` (its
``set_admit_ctrl_config``), ``set_compliance_type``, ``set_velocity_compliance``,
``set_compliance_condition``, ``set_force_control_frame``, ``enable_admittance``,
``set_tool_drive``, ``set_tool_drive_frame``, ``tool_drive_enable``, ``disable_force_control``,
``set_ft_sensor_payload`` / ``get_ft_sensor_payload``, ``set_ft_sensor_filter``,
``set_ft_sensor_soft_limit``. The twin's hand on the tool, ``~sim/push_tool``, is among the
twin's own services (:mod:`.twin_services`).

**Payload identification is an action** (``~identify_ft_sensor_payload``,
jaka_driver_msgs/IdentifySensorPayloadAction), not start/status services: it moves the arm
for seconds, so a ROS user expects what MoveIt and FollowJointTrajectory give — one goal,
feedback (progress 0–1, what it does), a result with the mass and centroid, and cancel, which
stops the arm. (JAKA's start / status / result calls are the controller's wire; phase 2 polls
them behind the same action.)

Topics and the latched state: :mod:`.force_topics`.
"""
from __future__ import annotations

import actionlib
import rospy
from std_srvs.srv import SetBool, SetBoolResponse, Trigger, TriggerResponse

from jaka_driver_msgs import srv as msgs
from jaka_driver_msgs.msg import (IdentifySensorPayloadAction, IdentifySensorPayloadFeedback,
                                  IdentifySensorPayloadResult)

from ..backend.force import SENSOR_FRAME
from ..common.results import Result
from ..driver import RobotDriver
from .force_topics import ForceTopics, fill_wrench, wrench_values


def advertise_force(driver: RobotDriver, also_publish: list) -> list:
    """Every force service, the identification action and the topics; ``also_publish`` is
    the state publisher's list of per-sample publishers (the wrench topics go there)."""
    f = driver.force
    topics = ForceTopics(driver)
    also_publish.append(topics.publish_sample)

    def answered(name: str, result: Result) -> Result:
        if not result.ok:
            rospy.logwarn("%s refused (%d): %s", name, result.code, result.message)
        topics.refresh()
        return result

    def ret(name, srv_type, call):
        response_type = srv_type._response_class

        def serve(req):
            result = answered(name, call(req))
            return response_type(ret=int(result.code), message=result.message)
        return name, srv_type, serve

    def set_bool(name, call):
        def serve(req):
            result = answered(name, call(req.data))
            return SetBoolResponse(success=result.ok, message=result.message)
        return name, SetBool, serve

    def trigger(name, call):
        def serve(_req):
            result = answered(name, call())
            return TriggerResponse(success=result.ok, message=result.message)
        return name, Trigger, serve

    def get_payload(_req):
        result = answered("get_ft_sensor_payload", f.sensor_payload())
        response = msgs.GetSensorPayloadResponse(ret=int(result.code), message=result.message)
        if result.ok:
            mass, c = result.value
            response.mass, (response.xc, response.yc, response.zc) = mass, c.tolist()
        return response

    def get_data(req):
        result = f.sensor_data(req.type)
        response = msgs.GetSensorDataResponse(ret=int(result.code), message=result.message)
        if result.ok:
            values, response.status, response.errcode = result.value
            response.wrench.header.stamp = rospy.Time.from_sec(driver.state().stamp)
            response.wrench.header.frame_id = SENSOR_FRAME
            fill_wrench(response.wrench.wrench, values)
        return response

    table = [
        ret("set_ft_sensor_payload", msgs.SetSensorPayload,
            lambda r: f.set_sensor_payload(r.mass, [r.xc, r.yc, r.zc])),
        ret("set_ft_sensor_filter", msgs.SetSensorFilter,
            lambda r: f.set_filter(r.cutoff_hz)),
        ret("set_ft_sensor_soft_limit", msgs.SetWrench,
            lambda r: f.set_soft_limit(wrench_values(r.wrench))),
        ret("set_admittance", msgs.SetAdmittance,
            lambda r: f.set_admittance(r.axis, r.opt, r.ft_user, r.ft_rebound, r.ft_constant,
                                       r.normal_track)),
        ret("set_compliance_type", msgs.SetComplianceType,
            lambda r: f.set_compliance_type(r.sensor_compensation, r.compliance_type)),
        ret("set_velocity_compliance", msgs.SetVelocityCompliance,
            lambda r: f.set_velocity_compliance(r.level, list(r.rates))),
        ret("set_compliance_condition", msgs.SetWrench,
            lambda r: f.set_compliance_condition(wrench_values(r.wrench))),
        ret("set_force_control_frame", msgs.SetForceFrame,
            lambda r: f.set_frame(r.frame)),
        ret("set_tool_drive", msgs.SetToolDrive,
            lambda r: f.set_tool_drive(r.axis, r.opt, r.rigidity, r.rebound)),
        ret("set_tool_drive_frame", msgs.SetForceFrame,
            lambda r: f.set_tool_drive_frame(r.frame)),
    ]
    table += [set_bool("ft_sensor_enable", f.sensor_enable),
              set_bool("enable_admittance", f.enable_admittance),
              set_bool("tool_drive_enable", f.enable_tool_drive),
              trigger("zero_ftsensor", f.zero_sensor),
              trigger("disable_force_control", f.disable)]
    services = [rospy.Service(f"~{name}", srv_type, serve) for name, srv_type, serve in table]
    services += [rospy.Service("~get_ft_sensor_payload", msgs.GetSensorPayload, get_payload),
                 rospy.Service("~get_ft_sensor_data", msgs.GetSensorData, get_data)]
    IdentificationAction(driver, topics.refresh)
    return services


class IdentificationAction:
    """``~identify_ft_sensor_payload``: one goal at a time; feedback every 0.1 s; cancel stops
    the arm (the result then says so, -12)."""

    def __init__(self, driver: RobotDriver, refresh):
        self._driver = driver
        self._refresh = refresh
        self._server = actionlib.SimpleActionServer(
            rospy.resolve_name("~identify_ft_sensor_payload"), IdentifySensorPayloadAction,
            execute_cb=self._execute, auto_start=False)
        self._server.start()

    def _execute(self, goal) -> None:
        server, driver = self._server, self._driver
        cancelled = []

        def feedback(status):
            if server.is_preempt_requested() and not cancelled:
                cancelled.append(True)
                driver.stop_move()
            server.publish_feedback(IdentifySensorPayloadFeedback(progress=status.progress,
                                                                  message=status.message))

        result = driver.force.identify_payload(list(goal.joint_positions), goal.apply,
                                               feedback, 0.1)
        self._refresh()
        answer = IdentifySensorPayloadResult(ret=int(result.code), message=result.message)
        if result.ok:
            mass, c = result.value
            answer.mass, (answer.xc, answer.yc, answer.zc) = float(mass), c.tolist()
            server.set_succeeded(answer, result.message)
        elif cancelled or server.is_preempt_requested():
            server.set_preempted(answer, result.message)
        else:
            rospy.logwarn("identify_ft_sensor_payload (%d): %s", result.code, result.message)
            server.set_aborted(answer, result.message)
