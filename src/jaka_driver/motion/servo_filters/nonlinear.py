"""JAKA's non-linear filters (NLF): "an online S-curve planner that tracks the target based on
jerk, acceleration and velocity limits" (JAKA's guide), per joint (``filter_type`` 2) or on the
TCP pose (4, servo_p only).

The tracker, per axis, each 8 ms cycle: the output is a triple integrator (position, velocity,
acceleration) driven by a jerk within ±``jerk``. The cycle's jerk is the one that brings the
point where the output would come to rest — braking at once, as fast as the limits allow — onto
the target; so the output heads for the target as fast as it can and arrives at a target that
stands still without overshooting it by more than one cycle's largest jerk step (J·T³: the
braking is planned as a continuous jerk, played in 8 ms pieces). Velocity and acceleration stay within ±``velocity``
and ±``accel`` (the jerk that would carry them past is not taken). Positions and limits share
one unit (rad and rad/s…, or m and m/s…).

The jerk is found on grids over [-jerk, jerk], each inside the last one's bracket (all axes at
once, in numpy): the resting point grows with the jerk, so the largest jerk whose resting point
does not pass the target is the one. Within one cycle's largest jerk of a target it stands
still, the output is the target: the discrete steps would otherwise circle it at that size.
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from ...common.transforms import matrix_to_rotvec, rotvec_to_matrix

_POINTS, _PASSES = 17, 4    # the jerk to 2 / 16⁴ of its range


def _integrate(p, v, a, j, t):
    """State after ``t`` s of constant jerk ``j`` (element-wise)."""
    return (p + v * t + a * t * t / 2 + j * t ** 3 / 6, v + a * t + j * t * t / 2, a + j * t)


def rest_offset(v, a, accel, jerk):
    """How far (element-wise) an axis moving at ``v`` with acceleration ``a`` travels before it
    comes to rest (v = 0, a = 0) braking as fast as ``accel`` and ``jerk`` allow: the
    acceleration ramps (at ±jerk) to a peak a1 opposite the velocity left after ramping a to 0,
    holds it at ±accel if it gets there, and ramps back to 0 as the velocity reaches 0."""
    v, a = np.asarray(v, float), np.asarray(a, float)
    v_after = v + a * np.abs(a) / (2 * jerk)
    s = -np.sign(v_after)                                     # the braking pulse's sign
    a1 = s * np.sqrt(np.maximum((a * a - 2 * jerk * s * v) / 2, 0.0))
    a1 = np.where(s == 0, a, a1)                              # ramping a to 0 stops it
    capped = np.abs(a1) > accel
    a1 = np.where(capped, s * accel, a1)
    hold = np.where(capped, (-s * v - (2 * accel * accel - a * a) / (2 * jerk)) / accel, 0.0)
    hold = np.maximum(hold, 0.0)
    p = np.zeros_like(v)
    t1 = np.abs(a1 - a) / jerk
    p, v1, _ = _integrate(p, v, a, np.sign(a1 - a) * jerk, t1)
    p, v2, _ = _integrate(p, v1, a1, 0.0, hold)
    t3 = np.abs(a1) / jerk
    p, _, _ = _integrate(p, v2, a1, -np.sign(a1) * jerk, t3)
    return p


class ThirdOrderTracker:
    """Tracks a target per axis (module doc); ``position``, ``velocity``, ``accel`` its state."""

    def __init__(self, velocity, accel, jerk, cycle: float):
        self.v_max, self.a_max, self.j_max = (np.asarray(x, float) for x in (velocity, accel,
                                                                              jerk))
        self.cycle = cycle
        self.position = self.velocity = self.accel = None

    def reset(self, position) -> None:
        """At rest at ``position``."""
        self.position = np.array(position, float)
        self.velocity = np.zeros_like(self.position)
        self.accel = np.zeros_like(self.position)

    def next(self, target) -> np.ndarray:
        target = np.asarray(target, float)
        p, v, a, T = self.position, self.velocity, self.accel, self.cycle
        A, J, V = self.a_max, self.j_max, self.v_max

        def after(j):
            return _integrate(p, v, a, j, T)

        def rests_beyond(j):            # rests past the target, or would break a limit
            p1, v1, a1 = after(j)
            over_v = v1 + a1 * np.abs(a1) / (2 * J) > V
            return (p1 + rest_offset(v1, a1, A, J) > target) | (a1 > A) | over_v

        def keeps_low(j):               # keeps the limits downwards
            p1, v1, a1 = after(j)
            return ~((a1 < -A) | (v1 + a1 * np.abs(a1) / (2 * J) < -V))

        full = J * np.ones_like(p)
        j = _last_false(rests_beyond, -full, full)   # the largest jerk that does not overshoot
        low = ~keeps_low(j)
        if np.any(low):                 # the smallest jerk that keeps the lower limits
            j = np.where(low, _last_false(keeps_low, j, full, first_true=True), j)
        self.position, self.velocity, self.accel = after(j)
        # within one cycle of the largest jerk of the target, at rest: there (the discrete
        # steps would otherwise circle it at that size)
        there = (np.abs(self.position - target) <= J * T ** 3 / 6) & \
            (np.abs(self.velocity) <= J * T * T / 2) & (np.abs(self.accel) <= J * T)
        self.position = np.where(there, target, self.position)
        self.velocity = np.where(there, 0.0, self.velocity)
        self.accel = np.where(there, 0.0, self.accel)
        return self.position.copy()


def _last_false(predicate, lo, hi, first_true: bool = False):
    """Per axis, the largest x in [lo, hi] with ``predicate(x)`` False (``predicate`` False up
    to a point, True beyond; ``lo`` if it is True everywhere) — or with ``first_true`` the
    smallest x where it is True (``hi`` if nowhere). Grids of :data:`_POINTS` points, each
    inside the bracket the last one found: :data:`_PASSES` passes, all axes at once."""
    lo, hi = np.array(lo, float), np.array(hi, float)
    steps = np.linspace(0.0, 1.0, _POINTS)[:, None]
    for _ in range(_PASSES):
        grid = lo + steps * (hi - lo)                     # (points, axes)
        true = predicate(grid)
        # index of the last False (the grid is False, then True)
        last = np.where(true.all(axis=0), -1, _POINTS - 1 - np.argmax(~true[::-1], axis=0))
        k = np.clip(last, 0, _POINTS - 2)
        cols = np.arange(grid.shape[1])
        lo, hi = np.where(last < 0, lo, grid[k, cols]), np.where(last < 0, lo, grid[k + 1, cols])
        hi = np.where(last == _POINTS - 1, grid[-1, cols], hi)
    return hi if first_true else lo


class JointNonlinear:
    """``filter_type`` 2: the tracker on each joint (rad; limits rad/s, rad/s², rad/s³)."""

    def __init__(self, velocity: float, accel: float, jerk: float, cycle: float):
        self._tracker = ThirdOrderTracker(velocity, accel, jerk, cycle)

    def reset(self, q, pose=None) -> None:
        self._tracker.reset(q)

    def next(self, q_target, pose=None) -> np.ndarray:
        return self._tracker.next(q_target)


class CartesianNonlinear:
    """``filter_type`` 4: the tracker on the TCP pose of servo_p targets — its position per axis
    (m; ``linear_*`` limits) and its attitude as the rotation vector from an anchor attitude
    (rad; the rotation limits), re-anchored on the filtered attitude whenever that is more than
    90° from the anchor — then the joints by IK near the last setpoint. A target without a pose
    (servo_j) passes unfiltered, as JAKA's header says. ``ik(T, seed)`` → joints or None;
    ``fk(q)`` → pose (4x4 m); where IK fails the joints hold and ``failures`` counts it."""

    def __init__(self, linear, angular, cycle: float,
                 ik: Callable[[np.ndarray, np.ndarray], Optional[np.ndarray]],
                 fk: Callable[[np.ndarray], np.ndarray]):
        self._position = ThirdOrderTracker(*linear, cycle)
        self._attitude = ThirdOrderTracker(*angular, cycle)
        self._ik, self._fk = ik, fk
        self._q = None
        self._anchor = np.eye(3)
        self.failures = 0

    def reset(self, q, pose=None) -> None:
        self._q = np.array(q, float)
        T = self._fk(self._q) if pose is None else np.asarray(pose, float)
        self._anchor = T[:3, :3].copy()
        self._position.reset(T[:3, 3])
        self._attitude.reset(np.zeros(3))

    def next(self, q_target, pose=None) -> np.ndarray:
        if pose is None:                                  # servo_j: not a Cartesian target
            self.reset(q_target)
            return np.array(q_target, float)
        pose = np.asarray(pose, float)
        position = self._position.next(pose[:3, 3])
        rotation = self._attitude.next(matrix_to_rotvec(self._anchor.T @ pose[:3, :3]))
        T = np.eye(4)
        T[:3, 3] = position
        T[:3, :3] = self._anchor @ rotvec_to_matrix(rotation)
        if np.linalg.norm(rotation) > np.pi / 2:         # keep the rotation vector continuous
            self._anchor = T[:3, :3].copy()
            self._attitude.position = np.zeros(3)
        q = self._ik(T, self._q)
        if q is None:
            self.failures += 1
            return self._q.copy()
        self._q = np.asarray(q, float)
        return self._q.copy()
