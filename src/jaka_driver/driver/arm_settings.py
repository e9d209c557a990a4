"""The arm's settings through the door: the speed ratio, tool and user frames, the payload,
drag mode, the collision level, the installation angle, IO, clearing an error, power and enable — and the kinematics a
request may ask for (``get_fk``, ``get_ik``, in the conventions the driver was built with).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from ..common.installation import installation
from ..common.results import Code, CommandRefused, Result, invalid
from ..conventions import cartesian
from . import checks as check
from .door import RequestPart, answers, note, with_notes


class SettingRequests(RequestPart):
    """Settings and kinematics (see the module)."""

    @answers
    def set_speed_ratio(self, ratio: float) -> Result:
        """Scale joint_move, linear_move, jog, velocity jogs and trajectories by ``ratio``
        in (0, 1], a controller's rapid rate: time × 1/ratio (speeds × ratio, accelerations ×
        ratio²). Servo targets are not scaled. Refused while the arm moves (a running move
        was planned at the old ratio)."""
        r = check.finite("ratio", ratio)
        if not 0.0 < r <= 1.0:
            raise invalid(f"ratio is {r:g}, expected in (0, 1] (1 = full speed)")
        if self.door.moving:
            raise CommandRefused(Code.BUSY, "speed ratio refused while the arm moves: set it "
                                 "between moves")
        return self.backend.set_speed_ratio(r)

    def speed_ratio(self) -> float:
        """The ratio the robot runs at (the controller's, read back)."""
        return float(self.backend.speed_ratio())

    @answers
    def set_toolframe(self, pose: Sequence[float], tool_num: int) -> Result:
        """Tool ``tool_num`` (1–11, 0 = flange) = ``pose`` (mm + rotvec, flange frame)."""
        num = check.integer_in("tool_num", tool_num, 0, 11)
        frame = np.eye(4) if num == 0 else check.frame_pose(pose, check.TOOL_REACH_MM)
        return self.backend.set_tool_frame(num, frame)

    @answers
    def set_userframe(self, pose: Sequence[float], user_num: int) -> Result:
        """User frame ``user_num`` (1–10, 0 = base) = ``pose`` (mm + rotvec, base frame)."""
        num = check.integer_in("user_num", user_num, 0, 10)
        frame = np.eye(4) if num == 0 else check.frame_pose(pose, check.USER_REACH_MM)
        return self.backend.set_user_frame(num, frame)

    @answers
    def set_payload(self, tool_num: int, mass: float, xc: float, yc: float, zc: float) -> Result:
        """Payload ``mass`` kg at (xc, yc, zc) mm in the flange frame; activates tool_num."""
        num = check.integer_in("tool_num", tool_num, 0, 11)
        m, centroid = check.payload(self.model, mass, (("xc", xc), ("yc", yc), ("zc", zc)))
        return self.backend.set_payload(num, m, centroid)

    @answers
    def drag_mode(self, on: bool) -> Result:
        """Free drive on or off; refused in servo mode or while moving."""
        if on:
            if self.door.moving:
                raise CommandRefused(Code.BUSY, "drag mode refused while the arm moves")
            self.door.ready()
        return self.backend.set_drag_mode(bool(on))

    @answers
    def set_collisionlevel(self, is_enable: bool, value: int) -> Result:
        """Detection off, or ``value`` 10–100 → level 1–4 (≤25, ≤50, ≤75, ≤100)."""
        if not is_enable:
            return self.backend.set_collision_level(0)
        v = check.integer_in("value", value, 10, 100)
        level = 1 if v <= 25 else 2 if v <= 50 else 3 if v <= 75 else 4
        return self.backend.set_collision_level(level)

    @answers
    def collision_level(self) -> Result:
        """The collision sensitivity level the arm holds (``value``: 0 off, 1–5)."""
        return self.backend.collision_level()

    @answers
    def set_installation_angle(self, tilt_x: float, rot_z: float) -> Result:
        """Mount the arm tilted ``tilt_x`` rad about x (0–π), then turned ``rot_z`` rad about z
        (0–2π); refused while the arm moves (its motion was planned under the old gravity)."""
        mounting = installation(tilt_x, rot_z)
        if self.door.moving:
            raise CommandRefused(Code.BUSY, "installation angle refused while the arm moves")
        return self.backend.set_installation_angle(mounting)

    @answers
    def installation_angle(self) -> Result:
        """How the arm is mounted, as the arm reports it (``value``: an
        :class:`~jaka_driver.common.installation.Installation`)."""
        return self.backend.installation_angle()

    @answers
    def set_io(self, signal: str, type: int, index: int, value: float) -> Result:  # noqa: A002
        """Set an output (docs/interface.md, "set_io"); digital non-zero → 1."""
        sig = check.io_signal(signal)
        check.io_address(self.model, sig, 1, type, index)
        v = check.io_value(sig, value, analog_limit=check.ANALOG_LIMIT)
        return self.backend.set_io(sig, int(type), int(index), v)

    @answers
    def get_io(self, signal: str, path: int, type: int, index: int) -> Result:  # noqa: A002
        """Read an IO point (docs/interface.md, "get_io"); value in ``Result.value``."""
        sig = check.io_signal(signal)
        check.io_address(self.model, sig, path, type, index)
        return self.backend.get_io(sig, int(path), int(type), int(index))

    @answers
    def clear_err(self) -> Result:
        """Clear a collision / protective stop / error; refused under e-stop."""
        if self.backend.state().emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed: release it "
                                 "first")
        self.door.jog.clear()
        return self.backend.clear_error()

    @answers
    def set_power(self, on: bool) -> Result:
        if not on:
            self.door.forget_jogs()
        elif self.backend.state().emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed")
        return self.backend.set_power(bool(on))

    @answers
    def set_enabled(self, on: bool) -> Result:
        st = self.backend.state()
        if on and st.emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed")
        if on and not st.powered:
            raise CommandRefused(Code.NOT_POWERED, "robot is not powered (call power)")
        if not on:
            self.door.jog.clear()
        return self.backend.set_enabled(bool(on))

    # ---- kinematics ---------------------------------------------------------------------------
    @answers
    def get_fk(self, joint: Sequence[float]) -> Result:
        """Pose (mm + rotvec, or RPY with ``jaka_code`` conventions) of the active tool in the
        active user frame at ``joint``."""
        q = check.vector("joint", joint)
        result = self.backend.forward_kinematics(q)
        if not result.ok:
            return result
        return Result.success(result.message,
                              cartesian.matrix_to_pose_mm(self.conventions, result.value))

    @answers
    def get_ik(self, ref_joint: Sequence[float], cartesian_pose: Sequence[float]) -> Result:
        """Joints (rad) nearest ``ref_joint`` reaching ``cartesian_pose`` (mm + rotvec, or RPY
        with ``jaka_code`` conventions); an empty ``ref_joint`` seeds from the current
        joints."""
        if len(ref_joint) == 0:
            ref = self.backend.state().joint_position
        else:
            ref = check.vector("ref_joint", ref_joint)
        pose = check.vector("cartesian_pose", cartesian_pose)
        target = cartesian.pose_to_matrix_mm(self.conventions, pose)
        notes: list[str] = []
        note(notes, cartesian.reading_note(self.conventions, "cartesian_pose", pose))
        result = self.backend.inverse_kinematics(target, ref)
        if not result.ok:
            return with_notes(result, notes)
        return with_notes(Result.success(result.message, [float(x) for x in result.value]),
                           notes)
