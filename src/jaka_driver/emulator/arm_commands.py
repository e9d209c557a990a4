"""The arm's commands: power and enable, state, motion (queued moves — ``joint_move``,
``moveL``, ``movc``, ``end_move`` —, jog, stop), servo mode,
kinematics, drag mode. Wire requests in (deg, mm + RPY deg, deg/s, mm/s), SI values to the
:class:`~.twin_controller.TwinController`, wire replies out (docs/protocol.md).
"""
from __future__ import annotations

import math
from typing import Callable, Dict, Mapping, Tuple

import numpy as np

from ..protocol import units
from ..protocol.fields import (ERROR_CODE_EXCEPTION, Cmd, CoordMap, Field, JogMode,
                               StatusField)
from ..protocol.status_encoder import encode_status
from .replies import ERROR_REQUEST, Answer, PlainFloats, RecordedReply, Rejected, done
from .status_packet import status_fields, wire_pose
from .twin_controller import TwinController
from .wire_fields import flag, integer, joints, number, pose

#: wire jog coord_map → the twin's coord (0 joint, 1 base, 2 tool)
_TWIN_COORD = {CoordMap.BASE: 1, CoordMap.JOINT: 0, CoordMap.TOOL: 2}
#: emergency_stop_status on fw 1.5.14, in every recorded run: no cmdName
ESTOP_STATUS_EXCEPTION = {Field.ERROR_CODE: ERROR_CODE_EXCEPTION,
                          Field.ERROR_MSG: "Exception:function call failed"}


def _relative(base: np.ndarray, increment: np.ndarray) -> np.ndarray:
    """A relative Cartesian command: translation added in the user frame, rotation applied
    about the user frame's axes (the emulator's reading of relFlag 1; not verified)."""
    out = np.eye(4)
    out[:3, :3] = increment[:3, :3] @ base[:3, :3]
    out[:3, 3] = base[:3, 3] + increment[:3, 3]
    return out


def _stopped(st) -> bool:
    """A protective stop stands (a collision is one, to a controller)."""
    return st.protective_stop or st.collision


class ArmCommands:
    def __init__(self, controller: TwinController):
        self.c = controller
        self.model = controller.model

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        c = self.c
        return {
            Cmd.POWER_ON: lambda r: done(c.set_power(True)),
            Cmd.POWER_OFF: lambda r: done(c.set_power(False)),
            Cmd.ENABLE_ROBOT: lambda r: done(c.set_enabled(True)),
            Cmd.DISABLE_ROBOT: lambda r: done(c.set_enabled(False)),
            Cmd.GET_ROBOT_STATE: self._get_robot_state,
            Cmd.EMERGENCY_STOP_STATUS: self._emergency_stop_status,
            Cmd.PROTECTIVE_STOP_STATUS: lambda r: Answer(
                {Field.PROTECTIVE_STOP: int(_stopped(c.state()))}),
            Cmd.CLEAR_ERROR: lambda r: done(c.clear_error()),
            Cmd.JOINT_MOVE: self._joint_move,
            Cmd.MOVE_L: self._move_l,
            "move_l": self._move_l,   # the other spelling clients use
            Cmd.MOVC: self._movc,
            Cmd.END_MOVE: self._end_move,
            Cmd.JOG: self._jog,
            Cmd.STOP_PROGRAM: lambda r: done(c.stop()),
            Cmd.GET_MOTION_STATE: self._get_motion_state,
            Cmd.WAIT_COMPLETE: self._wait_complete,
            Cmd.IS_ON_LIMIT: lambda r: Answer({Field.ON_LIMIT: int(c.on_limit())}),
            Cmd.SERVO_MOVE: lambda r: done(c.set_servo_mode(
                integer(r, Field.REL_FLAG, 0, 1) == 1)),
            Cmd.IS_IN_SERVOMOVE: lambda r: Answer({Field.IN_SERVOMOVE: bool(c.state().servo_mode)}),
            Cmd.SERVO_J: self._servo_j,
            Cmd.SERVO_P: self._servo_p,
            Cmd.GET_JOINT_POS: lambda r: Answer(
                {Field.JOINT_POS: units.joints_to_wire(c.state().joint_position)}),
            Cmd.GET_TCP_POS: lambda r: Answer({Field.TCP_POS: wire_pose(c.state().tcp_pose)}),
            Cmd.GET_DATA: self._get_data,
            Cmd.KINE_FORWARD: self._kine_forward,
            Cmd.KINE_INVERSE: self._kine_inverse,
            Cmd.DRAG_STATUS: lambda r: Answer({Field.DRAG_STATUS: int(c.state().drag_mode)}),
            Cmd.GET_DRAG_STATUS: lambda r: Answer({Field.STATUS: bool(c.state().drag_mode)}),
            Cmd.TORQUE_CONTROL_ENABLE: self._torque_control_enable,
            Cmd.TORQUE_FEEDFORWARD: lambda r: Answer(),   # the twin's drives have no such input
        }

    # ---- state ----------------------------------------------------------------------------------
    def _get_robot_state(self, _req) -> Answer:
        t = self.c.state()
        return Answer({Field.ENABLE: "robot_enabled" if t.enabled else "robot_disabled",
                       Field.POWER: "powered_on" if t.powered else "powered_off"})

    def _emergency_stop_status(self, _req) -> Answer:
        if self.c.profile.estop_status_fails:
            raise RecordedReply(dict(ESTOP_STATUS_EXCEPTION))
        return Answer({Field.EMERGENCY_STOP: int(self.c.state().emergency_stop)})

    def _get_data(self, _req) -> Answer:
        """The status packet as a reply, written as the packet is (plain floats)."""
        fields = status_fields(self.c)
        # ``len`` as in the status packet with the same fields
        return Answer(PlainFloats({StatusField.LEN: len(encode_status(fields)), **fields}))

    # ---- queued motion --------------------------------------------------------------------------
    def _joint_speed(self, req) -> Tuple[float, float]:
        """A joint-interpolated move's speed and accel (wire deg/s, deg/s² → rad/s, rad/s²).
        Without accel (a fw 1.4.11 client sends none) the joints' own limit is used."""
        speed = math.radians(number(req, Field.SPEED, positive=True))
        default_accel = math.degrees(self.model.default_joint_accel)
        return speed, math.radians(number(req, Field.ACCEL, default=default_accel,
                                          positive=True))

    def _joint_move(self, req) -> Answer:
        q = joints(req)
        relative = integer(req, Field.REL_FLAG, 0, 1, default=0)
        speed, accel = self._joint_speed(req)
        # A relative move adds to where the move before it ends: resolved when its turn comes.
        self.c.joint_move((lambda: self.c.commanded_joints() + q) if relative else (lambda: q),
                          speed, accel)
        return Answer()

    def _move_l(self, req) -> Answer:
        target = pose(req, Field.CART_POSITION)
        relative = integer(req, Field.REL_FLAG, 0, 1, default=0)
        speed = number(req, Field.SPEED, positive=True) / 1000.0
        default_accel = self.model.default_tcp_accel * 1000.0      # the wire's mm/s²
        accel = number(req, Field.ACCEL, default=default_accel, positive=True) / 1000.0
        self.c.linear_move((lambda: _relative(self.c.commanded_tcp(), target)) if relative
                           else (lambda: target), speed, accel)
        return Answer()

    def _movc(self, req) -> Answer:
        """``movc`` as JAKA's SDK writes it (docs/protocol.md, "Circular moves"): ``pos_mid``
        and ``pos_end`` (mm + RPY deg; with ``relFlag`` 1 relative to where the move before it
        ends, as ``moveL``'s), ``speed`` mm/s and ``accel`` mm/s² (as ``moveL``'s: JAKA's header
        says rad/s, no controller reply says which), ``circle_cnt`` more turns (a double),
        ``circle_mode`` 0–3 (the attitude rule); ``tol`` (blending) and ``executing_line_id``
        (the client's counter) are read and not used: the twin does not blend."""
        mid, end = pose(req, Field.POS_MID), pose(req, Field.POS_END)
        relative = integer(req, Field.REL_FLAG, 0, 1, default=0)
        speed = number(req, Field.SPEED, positive=True) / 1000.0
        default_accel = self.model.default_tcp_accel * 1000.0      # the wire's mm/s²
        accel = number(req, Field.ACCEL, default=default_accel, positive=True) / 1000.0
        turns = number(req, Field.CIRCLE_CNT, default=0.0, lo=0.0)
        mode = integer(req, Field.CIRCLE_MODE, 0, 3, default=0)
        number(req, Field.TOL, default=0.0, lo=0.0)

        def poses():
            if not relative:
                return mid, end
            here = self.c.commanded_tcp()
            return _relative(here, mid), _relative(here, end)
        self.c.circular_move(poses, speed, accel, turns, mode)
        return Answer()

    def _end_move(self, req) -> Answer:
        target = pose(req, Field.END_POSITION)
        self.c.end_move(target, *self._joint_speed(req))
        return Answer()

    def _get_motion_state(self, _req) -> Answer:
        c = self.c
        return Answer({Field.MOTION_LINE: c.motion_line, Field.ERR_ADD_LINE: 0,
                       Field.QUEUE: c.queued, Field.ACTIVE_QUEUE: c.queue.active,
                       Field.QUEUE_FULL: 0, Field.INPOS: bool(c.inpos)})

    def _wait_complete(self, _req) -> Answer:
        # The server waits for the queue outside its command lock (see server.py); this is
        # reached once the queue is done, or after the server's limit.
        if not self.c.inpos:
            raise Rejected("wait_complete: the motion did not complete")
        return Answer()

    def _jog(self, req) -> Answer:
        mode = integer(req, Field.JOG_MODE, 0, 3)
        if mode == JogMode.STOP:
            # any jog ends (continuous, incremental, absolute), whatever the axis: JAKA's SDK
            # stops all axes with jnum -1, and a stop needs no more than the mode
            self.c.jog_stop()
            return Answer()
        coord_map = CoordMap(integer(req, Field.COORD_MAP, 0, 2))
        axis = integer(req, Field.JNUM, 0, 5)
        angular = coord_map == CoordMap.JOINT or axis >= 3
        velocity = number(req, Field.JOGVEL)
        speed = math.radians(abs(velocity)) if angular else abs(velocity) / 1000.0
        if speed == 0:
            raise Rejected("jog: 'jogvel' must not be 0", ERROR_REQUEST)
        if mode == JogMode.CONTINUOUS:
            self.c.jog(_TWIN_COORD[coord_map], axis, 1 if velocity > 0 else -1, speed)
            return Answer()
        if coord_map != CoordMap.JOINT:
            raise Rejected("jog: the emulator does Cartesian jogs in continuous mode only "
                           "(jog_mode 1)", ERROR_REQUEST)
        # Increment (2) and absolute (3) joint jogs are queued joint moves of one axis.
        position = math.radians(number(req, Field.POSCMD))

        def target() -> np.ndarray:
            q = self.c.commanded_joints()
            q[axis] = q[axis] + position if mode == JogMode.INCREMENT else position
            return q
        accel = float(self.model.max_acceleration[axis])
        self.c.joint_move(target, min(speed, float(self.model.max_velocity[axis])), accel,
                          what="jog")
        return Answer()

    # ---- servo mode -----------------------------------------------------------------------------
    def _steps(self, req) -> int:
        # an unsigned int, 0 refused by the SDK itself; no upper bound on record (1000 sent)
        return integer(req, Field.STEP_NUM, 1, (1 << 32) - 1, default=1)

    def _servo_j(self, req) -> Answer:
        self.c.require_servo_mode(Cmd.SERVO_J)
        q = joints(req)
        if integer(req, Field.REL_FLAG, 0, 1, default=0):
            q = self.c.servo_reference(Cmd.SERVO_J) + q
        self.c.servo_joints(q, self._steps(req))
        return Answer()

    def _servo_p(self, req) -> Answer:
        self.c.require_servo_mode(Cmd.SERVO_P)
        target = pose(req, Field.SERVO_CART_POSITION)
        if integer(req, Field.REL_FLAG, 0, 1, default=0):
            here = self.c.forward_kinematics(self.c.servo_reference(Cmd.SERVO_P), "servo_p")
            target = _relative(here, target)
        self.c.servo_pose(target, self._steps(req))
        return Answer()

    # ---- kinematics -----------------------------------------------------------------------------
    def _kine_forward(self, req) -> Answer:
        pose_ = self.c.forward_kinematics(joints(req), "kine_forward")
        return Answer({Field.CART_POSITION: wire_pose(pose_)})

    def _kine_inverse(self, req) -> Answer:
        ref = joints(req)
        q = self.c.inverse_kinematics(pose(req, Field.CART_POSITION), ref, "kine_inverse")
        return Answer({Field.JOINT_POSITION: units.joints_to_wire(q)})

    # ---- drag mode -------------------------------------------------------------------
    def _torque_control_enable(self, req) -> Answer:
        self.c.set_drag_mode(flag(req, Field.ENABLE_FLAG))
        return Answer()
