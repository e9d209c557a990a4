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

import math
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


def displaced_pose(pose: np.ndarray, delta, in_tool: bool) -> np.ndarray:
    """``pose`` (4x4, m) moved by ``delta`` (dx, dy, dz m, rotation vector rad): in the tool
    frame (``in_tool``), or along base axes with the rotation about base axes at the TCP."""
    d = delta.tolist() if isinstance(delta, np.ndarray) else [float(x) for x in delta]
    rotation = rotvec_to_matrix(d[3:]) if any(d[3:]) else None   # none: the identity
    if in_tool:
        step = np.eye(4)
        step[:3, 3] = d[:3]
        if rotation is not None:
            step[:3, :3] = rotation
        return pose @ step
    moved = pose.copy()
    moved[:3, 3] += d[:3]
    if rotation is not None:
        moved[:3, :3] = rotation @ pose[:3, :3]
    return moved


class TwistRamp:
    """The jog's velocity (6-vector), moved towards the commanded twist by at most
    ``linear_accel`` (m/s²) on its linear part and ``angular_accel`` (rad/s²) on its angular
    part per second, each as a vector (the direction of travel turns, it does not zig-zag)."""

    def __init__(self, linear_accel: float, angular_accel: float):
        self.accel = (float(linear_accel), float(angular_accel))
        self.velocity = np.zeros(6)
        #: :attr:`velocity` as plain floats, as :meth:`update` left it
        self.values = [0.0] * 6
        self.target = np.zeros(6)

    def command(self, twist: np.ndarray) -> None:
        self.target = np.asarray(twist, float).copy()

    def stop(self) -> None:
        self.target = np.zeros(6)

    def update(self, dt: float) -> np.ndarray:
        # plain floats: six numbers a cycle, where numpy's calls cost more than the arithmetic
        v, t = self.velocity.tolist(), self.target.tolist()
        for first, accel in zip((0, 3), self.accel):
            gap = [t[k] - v[k] for k in range(first, first + 3)]
            size = math.sqrt(gap[0] * gap[0] + gap[1] * gap[1] + gap[2] * gap[2])
            step = accel * dt
            for k, g in zip(range(first, first + 3), gap):
                v[k] = t[k] if size <= step else v[k] + g * (step / size)
        self.velocity[:] = v
        self.values = v
        return self.velocity

    @property
    def at_rest(self) -> bool:
        return not self.velocity.any() and not self.target.any()


class VelocityJog:
    """One velocity jog's integration (see the module). ``measure(q)`` → (the TCP pose 4x4 m,
    the smallest singular value of the TCP's Jacobian 6x6, m and rad) and ``ik(pose, seed)``
    (joints or None) are the arm's kinematics with the active tool (:func:`on_arm` takes them
    from a :class:`~jaka_driver.kinematics.Kinematics`); ``lower``, ``upper`` (rad),
    ``max_velocity`` (rad/s), ``max_acceleration`` (rad/s²) its joints; ``linear_accel`` m/s²,
    ``angular_accel`` rad/s² the ramp's; ``cycle`` s.

    Each cycle measures the arm once: the step's end, measured for its singularity check, is
    the next cycle's start whenever the step is taken whole (only a slowed step measures its
    own end the next cycle)."""

    def __init__(self, *, measure: Callable, ik: Callable, lower, upper, max_velocity,
                 max_acceleration, linear_accel: float, angular_accel: float, in_tool: bool,
                 cycle: float):
        self._measure, self._ik = measure, ik
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)
        self.max_step = JOINT_SPEED_SHARE * np.asarray(max_velocity, float) * cycle
        self.max_acceleration = np.asarray(max_acceleration, float)
        # plain floats for the per-joint checks of each cycle (six of them: Python's own
        # arithmetic beats numpy's calls there)
        self._limits = list(zip(self.lower.tolist(), self.upper.tolist(),
                                self.max_step.tolist(), self.max_acceleration.tolist()))
        self._jump = (CONFIGURATION_JUMP * self.max_step).tolist()
        self.ramp = TwistRamp(linear_accel, angular_accel)
        self.in_tool = in_tool
        self.cycle = cycle
        #: why the last step was slowed or held (None: it was not)
        self.limited_by: Optional[str] = None
        #: (joints, pose, σ_min) measured last, at the end of the last step
        self._measured: Optional[tuple] = None

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
        self.ramp.update(self.cycle)
        velocity = self.ramp.values                 # the ramp's, as plain floats
        if not any(velocity):
            self.limited_by = None
            return q
        qs = q.tolist()
        pose, sigma = self._at(q, qs)
        cycle = self.cycle
        target = displaced_pose(pose, [v * cycle for v in velocity], self.in_tool)
        solution = self._ik(target, q)
        if solution is None:
            return self._held(q, "no IK solution for the next step")
        step = solution - q                          # the IK's joints: a float64 array
        steps = step.tolist()
        if any(abs(d) > most for d, most in zip(steps, self._jump)):
            # not a faster motion but another configuration (a joint wrapped by 2π, the wrist
            # flipped): no fraction of that step lies on the path
            return self._held(q, "the next step needs another arm configuration")
        after = q + step
        scale, why = self._scale(qs, steps, sigma, after)
        if scale <= 0.0:
            return self._held(q, why)
        self.limited_by = why if scale < 1.0 else None
        if scale < 1.0:
            self.ramp.velocity *= scale     # the ramp accelerates again from the slower speed
            self.ramp.values = self.ramp.velocity.tolist()
            return q + scale * step
        return after

    def _at(self, q: np.ndarray, qs: list) -> tuple[np.ndarray, float]:
        """(TCP pose, σ_min) at ``q`` (``qs`` its values): last cycle's measurement of the
        step's end when ``q`` is that end, else measured now."""
        measured = self._measured
        if measured is not None and measured[0] == qs:
            return measured[1], measured[2]
        return self._measure(q)

    def _held(self, q: np.ndarray, why: str) -> np.ndarray:
        self.ramp.velocity[:] = 0.0
        self.ramp.values = [0.0] * 6
        self.limited_by = why
        return q

    def _scale(self, qs: list, steps: list, sigma_now: float,
               after: np.ndarray) -> tuple[float, Optional[str]]:
        """The factor (0–1) for the step ``steps`` from ``qs`` (σ_min there ``sigma_now``; rad,
        as lists) to ``after``, and what set it."""
        scale, why = 1.0, None
        if not any(abs(d) > 1e-12 for d in steps):
            return 1.0, None
        # joint speeds, then joint limits (brake to rest at the limit); the first joint with
        # the lowest ratio names the reason, as an argmin would
        speed = brake = math.inf
        speed_j = brake_j = 0
        for j, (x, d, (lo, hi, most, accel)) in enumerate(zip(qs, steps, self._limits)):
            size = abs(d)
            if not size > 1e-12:
                continue
            ratio = most / size
            if ratio < speed:
                speed, speed_j = ratio, j
            left = max((hi - x if d > 0 else x - lo) - LIMIT_MARGIN, 0.0)
            allowed = min(math.sqrt(2.0 * accel * left) * self.cycle, left)
            ratio = allowed / size
            if ratio < brake:
                brake, brake_j = ratio, j
        if speed < scale:
            scale, why = speed, f"joint {speed_j + 1} at its speed limit"
        if brake < scale:
            scale, why = brake, f"joint {brake_j + 1} near its limit"
        # singularities: only a step that makes the arm more singular slows
        pose_after, sigma_after = self._measure(after)
        self._measured = (after.tolist(), pose_after, sigma_after)
        if sigma_after < sigma_now:
            factor = min(max((sigma_after - SINGULAR_STOP) / (SINGULAR_SLOW - SINGULAR_STOP),
                             0.0), 1.0)
            if factor < scale:
                scale, why = factor, (f"near a singularity (σ_min {sigma_after:.3f}, slowing "
                                      f"below {SINGULAR_SLOW:g}, stop at {SINGULAR_STOP:g})")
        return max(scale, 0.0), why


def on_arm(kinematics, model, tool, *, in_tool: bool, ratio: float, cycle: float,
           angular_accel: float) -> VelocityJog:
    """A velocity jog of ``model``'s arm through ``kinematics`` (a
    :class:`~jaka_driver.kinematics.Kinematics`) with the TCP at ``tool`` (4x4, m, in the
    flange frame), at the speed ratio ``ratio`` (the ramp's accelerations × ratio²: the
    twin's and a controller's, scaled in time as moves are); ``angular_accel`` rad/s² at
    ratio 1."""
    tool = np.array(tool, dtype=float)
    r2 = ratio ** 2
    return VelocityJog(measure=kinematics.tcp_measure(tool),
                       ik=kinematics.seeded_ik(tool), lower=model.lower, upper=model.upper,
                       max_velocity=model.max_velocity,
                       max_acceleration=model.max_acceleration,
                       linear_accel=model.max_tcp_accel * r2,
                       angular_accel=angular_accel * r2, in_tool=in_tool, cycle=cycle)
