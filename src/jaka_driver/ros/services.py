"""The driver's services: request message → RobotDriver call → response message.

Names are private to the node (``~joint_move`` → ``/jaka_driver/joint_move``, or
``/<ns>/jaka_driver/joint_move`` in a namespace). Every handler answers; failures are in
``ret``/``message`` (or ``success``, or the official driver's -999999 / 9999 markers), never in
a failed ROS call.
"""
from __future__ import annotations

import logging

import rospy
from std_srvs.srv import Empty, EmptyResponse, SetBool, SetBoolResponse

from jaka_driver_msgs.srv import GetCollisionLevel, GetCollisionLevelResponse
from jaka_msgs import srv as jaka

from ..driver import RobotDriver
from .service_answers import answer_with as _ret, logged as _logged

log = logging.getLogger(__name__)

GET_IO_FAILED = -999999.0   # the official driver's marker for a failed get_io
KINEMATICS_FAILED = [9999.0] * 6


def advertise(driver: RobotDriver) -> list[rospy.Service]:
    """Advertise every service of docs/interface.md; returns them so the node can shut them down.
    (Where JAKA's document and JAKA's driver code differ, requests are read as the driver was
    built to: ``~conventions``, jaka_driver.conventions.)"""
    d = driver
    move = _ret(jaka.MoveResponse)
    servo = _ret(jaka.ServoMoveResponse)

    def get_io(req):
        result = d.get_io(req.signal, req.path, req.type, req.index)
        if result.ok:
            return jaka.GetIOResponse(value=float(result.value), message=result.message)
        return jaka.GetIOResponse(value=GET_IO_FAILED, message=f"error: {result.message}")

    def get_fk(req):
        result = d.get_fk(req.joint)
        if result.ok:
            return jaka.GetFKResponse(cartesian_pose=result.value, message=result.message)
        return jaka.GetFKResponse(cartesian_pose=KINEMATICS_FAILED,
                                  message=f"error: {result.message}")

    def get_ik(req):
        result = d.get_ik(req.ref_joint, req.cartesian_pose)
        if result.ok:
            return jaka.GetIKResponse(joint=result.value, message=result.message)
        return jaka.GetIKResponse(joint=KINEMATICS_FAILED, message=f"error: {result.message}")

    def set_bool(method):
        def serve(req):
            result = method(req.data)
            if not result.ok:
                rospy.logwarn("refused (%d): %s", result.code, result.message)
            return SetBoolResponse(success=result.ok, message=result.message)
        return serve

    def get_collision_level(_req):
        result = d.collision_level()
        level = int(result.value) if result.ok else -1
        return GetCollisionLevelResponse(level=level, ret=int(result.code),
                                         message=result.message)

    def stop_move(_req):
        result = d.stop_move()
        rospy.loginfo("stop_move: %s", result.message)
        return EmptyResponse()

    table = [
        ("joint_move", jaka.Move, lambda r: move(d.joint_move(r.pose, r.mvvelo, r.mvacc,
                                                              r.mvtime))),
        ("linear_move", jaka.Move, lambda r: move(d.linear_move(
            r.pose, r.mvvelo, r.mvacc, r.coord_mode, r.has_ref, r.ref_joint))),
        ("jog", jaka.Move, lambda r: move(d.jog(r.coord_mode, r.index, r.mvvelo, r.mvacc))),
        ("servo_move_enable", jaka.ServoMoveEnable,
         lambda r: _ret(jaka.ServoMoveEnableResponse)(d.servo_move_enable(r.enable))),
        ("servo_j", jaka.ServoMove, lambda r: servo(d.servo_j(r.pose))),
        ("servo_p", jaka.ServoMove, lambda r: servo(d.servo_p(r.pose))),
        ("set_toolframe", jaka.SetTcpFrame,
         lambda r: _ret(jaka.SetTcpFrameResponse)(d.set_toolframe(r.pose, r.tool_num))),
        ("set_userframe", jaka.SetUserFrame,
         lambda r: _ret(jaka.SetUserFrameResponse)(d.set_userframe(r.pose, r.user_num))),
        ("set_payload", jaka.SetPayload, lambda r: _ret(jaka.SetPayloadResponse)(
            d.set_payload(r.tool_num, r.mass, r.xc, r.yc, r.zc))),
        ("set_collisionlevel", jaka.SetCollision, lambda r: _ret(jaka.SetCollisionResponse)(
            d.set_collisionlevel(r.is_enable, r.value))),
        ("set_io", jaka.SetIO, lambda r: _ret(jaka.SetIOResponse)(
            d.set_io(r.signal, r.type, r.index, r.value))),
        ("clear_err", jaka.ClearErr, lambda r: _ret(jaka.ClearErrResponse)(d.clear_err())),
        ("clear_error", jaka.ClearError, lambda r: _ret(jaka.ClearErrorResponse)(d.clear_err())),
    ]
    services = [rospy.Service(f"~{name}", srv_type, _logged(name, handler))
                for name, srv_type, handler in table]
    services += [
        rospy.Service("~get_io", jaka.GetIO, get_io),
        rospy.Service("~get_fk", jaka.GetFK, get_fk),
        rospy.Service("~get_ik", jaka.GetIK, get_ik),
        rospy.Service("~stop_move", Empty, stop_move),
        rospy.Service("~get_collision_level", GetCollisionLevel, get_collision_level),
        rospy.Service("~drag_mode", SetBool, set_bool(d.drag_mode)),
        rospy.Service("~drag_move", SetBool, set_bool(d.drag_mode)),
        rospy.Service("~power", SetBool, set_bool(d.set_power)),
        rospy.Service("~enable", SetBool, set_bool(d.set_enabled)),
    ]
    return services
