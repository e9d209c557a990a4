"""A velocity jog: the arm's TCP follows a commanded twist (6-D Cartesian velocity), one 8 ms
cycle at a time, slowing down and stopping safely before joint limits and singularities.

What a teleop device streams (``geometry_msgs/TwistStamped``) becomes, each cycle, a joint
setpoint: the twist is ramped at the jog's accelerations (the commanded twist may jump, the
TCP's velocity does not), integrated over the cycle into a displaced TCP pose (the jog's
composition, :func:`displaced_pose`), solved by IK seeded at the last setpoint, and the joint
step is then scaled by one factor ``s`` in [0, 1] (the TCP slows along its path, never leaves
it, never jumps):

- **joint speeds**: no joint faster than its limit;
- **joint limits**: a joint heading for its limit may move at most at the speed from which its
  acceleration stops it there (``sqrt(2 a d)``, ``d`` the distance left): it brakes to rest
  at the limit;
- **singularities**: when the step makes the arm more singular, the smallest singular value
  ``σ`` of the Jacobian (the tool's, m and rad) scales the step from 1 at
  :data:`SINGULAR_SLOW` down to 0 at :data:`SINGULAR_STOP`; a step that makes it less
  singular is free, so the arm can always be driven back out.

The ramp keeps the scaled velocity, so speed comes back at the jog's acceleration when a limit
is left. A step that finds no IK solution holds the arm (``s`` = 0). Units: m, rad, s; twists
(vx, vy, vz, wx, wy, wz) in m/s and rad/s, in the base frame (translation along base axes,
rotation about base axes at the TCP) or in the tool frame, as the Cartesian jog's coordinates.
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from ..common.results import Result
from ..common.transforms import rotvec_to_matrix

#: σ_min of the tool Jacobian below which a step towards a singularity slows, and at which it
#: stops. For a Zu 5 these are the wrist's J5 at ~0.2 rad and ~0.04 rad from 0 (or the elbow's
#: J3 at ~0.12 rad and ~0.025 rad).
SINGULAR_SLOW = 0.05
SINGULAR_STOP = 0.01
#: Fraction of a joint's speed limit a velocity jog may use: the rest is headroom for the IK's
#: step-to-step changes near a slowdown.
JOINT_SPEED_SHARE = 0.9
#: A joint step this many times its speed limit is another IK configuration, not a speed
CONFIGURATION_JUMP = 4.0
#: Distance (rad) kept from a joint limit (the stop lands this short of it).
LIMIT_MARGIN = 1e-3


def displaced_pose(pose: np.ndarray, delta: np.ndarray, in_tool: bool) -> np.ndarray:
    """``pose`` (4x4, m) moved by ``delta`` (dx, dy, dz m, rotation vector rad): in the tool
    frame (``in_tool``), or along base axes with the rotation about base axes at the TCP."""
    step = np.eye(4)
    step[:3, 3] = delta[:3]
    step[:3, :3] = rotvec_to_matrix(delta[3:])
    if in_tool:
        return pose @ step
    moved = pose.copy()
    moved[:3, 3] += step[:3, 3]
    moved[:3, :3] = step[:3, :3] @ pose[:3, :3]
    return moved


class TwistRamp:
    """The jog's velocity (6-vector), moved towards the commanded twist by at most
    ``linear_accel`` (m/s²) on its linear part and ``angular_accel`` (rad/s²) on its angular
    part per second, each as a vector (the direction of travel turns, it does not zig-zag)."""

    def __init__(self, linear_accel: float, angular_accel: float):
        self.accel = (float(linear_accel), float(angular_accel))
        self.velocity = np.zeros(6)
        self.target = np.zeros(6)

    def command(self, twist: np.ndarray) -> None:
        self.target = np.asarray(twist, float).copy()

    def stop(self) -> None:
        self.target = np.zeros(6)

    def update(self, dt: float) -> np.ndarray:
        for part, accel in zip((slice(0, 3), slice(3, 6)), self.accel):
            gap = self.target[part] - self.velocity[part]
            size = float(np.linalg.norm(gap))
            step = accel * dt
            self.velocity[part] = self.target[part] if size <= step else \
                self.velocity[part] + gap * (step / size)
        return self.velocity

    @property
    def at_rest(self) -> bool:
        return not self.velocity.any() and not self.target.any()


class VelocityJog:
    """One velocity jog's integration (see the module). ``tcp_pose(q)`` and ``ik(pose, seed)``
    (joints or None) and ``jacobian(q)`` (6x6) are the arm's kinematics with the active tool;
    ``lower``, ``upper`` (rad), ``max_velocity`` (rad/s), ``max_acceleration`` (rad/s²) its
    joints; ``linear_accel`` m/s², ``angular_accel`` rad/s² the ramp's; ``cycle`` s."""

    def __init__(self, *, tcp_pose: Callable, ik: Callable, jacobian: Callable, lower, upper,
                 max_velocity, max_acceleration, linear_accel: float, angular_accel: float,
                 in_tool: bool, cycle: float):
        self._tcp, self._ik, self._jacobian = tcp_pose, ik, jacobian
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)
        self.max_step = JOINT_SPEED_SHARE * np.asarray(max_velocity, float) * cycle
        self.max_acceleration = np.asarray(max_acceleration, float)
        self.ramp = TwistRamp(linear_accel, angular_accel)
        self.in_tool = in_tool
        self.cycle = cycle
        #: why the last step was slowed or held (None: it was not)
        self.limited_by: Optional[str] = None

    def progress(self) -> Result:
        """The answer to a twist: success, saying what the jog does now; its ``value`` is why
        the last step was slowed or held (:attr:`limited_by`), None when it was not."""
        why = self.limited_by
        return Result.success("following the twist" + (f" (slowed: {why})" if why else ""),
                              why)

    def command(self, twist: np.ndarray) -> None:
        """Ramp towards ``twist`` (m/s, rad/s) from the next cycle."""
        self.ramp.command(twist)

    def stop(self) -> None:
        self.ramp.stop()

    @property
    def at_rest(self) -> bool:
        return self.ramp.at_rest

    def next(self, q: np.ndarray) -> np.ndarray:
        """The setpoint (rad) one cycle after ``q`` (the last setpoint)."""
        velocity = self.ramp.update(self.cycle)
        if not velocity.any():
            self.limited_by = None
            return q
        target = displaced_pose(self._tcp(q), velocity * self.cycle, self.in_tool)
        solution = self._ik(target, q)
        if solution is None:
            return self._held(q, "no IK solution for the next step")
        step = np.asarray(solution, float) - q
        if np.any(np.abs(step) > CONFIGURATION_JUMP * self.max_step):
            # not a faster motion but another configuration (a joint wrapped by 2π, the wrist
            # flipped): no fraction of that step lies on the path
            return self._held(q, "the next step needs another arm configuration")
        scale, why = self._scale(q, step)
        if scale <= 0.0:
            return self._held(q, why)
        self.limited_by = why if scale < 1.0 else None
        if scale < 1.0:
            self.ramp.velocity *= scale     # the ramp accelerates again from the slower speed
            return q + scale * step
        return q + step

    def _held(self, q: np.ndarray, why: str) -> np.ndarray:
        self.ramp.velocity[:] = 0.0
        self.limited_by = why
        return q

    def _scale(self, q: np.ndarray, step: np.ndarray) -> tuple[float, Optional[str]]:
        """The factor (0–1) for ``step`` from ``q``, and what set it."""
        scale, why = 1.0, None
        moving = np.abs(step) > 1e-12
        if not moving.any():
            return 1.0, None
        ratio = np.where(moving, self.max_step / np.maximum(np.abs(step), 1e-12), np.inf)
        j = int(np.argmin(ratio))
        if ratio[j] < scale:
            scale, why = float(ratio[j]), f"joint {j + 1} at its speed limit"
        # joint limits: brake to rest at the limit
        left = np.where(step > 0, self.upper - q, q - self.lower) - LIMIT_MARGIN
        allowed = np.sqrt(2.0 * self.max_acceleration * np.maximum(left, 0.0)) * self.cycle
        allowed = np.minimum(allowed, np.maximum(left, 0.0))
        ratio = np.where(moving, allowed / np.maximum(np.abs(step), 1e-12), np.inf)
        j = int(np.argmin(ratio))
        if ratio[j] < scale:
            scale, why = float(ratio[j]), f"joint {j + 1} near its limit"
        # singularities: only a step that makes the arm more singular slows
        now = _smallest_singular_value(self._jacobian(q))
        after = _smallest_singular_value(self._jacobian(q + step))
        if after < now:
            factor = float(np.clip((after - SINGULAR_STOP) / (SINGULAR_SLOW - SINGULAR_STOP),
                                   0.0, 1.0))
            if factor < scale:
                scale, why = factor, (f"near a singularity (σ_min {after:.3f}, slowing below "
                                      f"{SINGULAR_SLOW:g}, stop at {SINGULAR_STOP:g})")
        return max(scale, 0.0), why


def _smallest_singular_value(jacobian: np.ndarray) -> float:
    return float(np.linalg.svd(jacobian, compute_uv=False)[-1])
