"""Time laws for point-to-point moves that start and end at rest.

:class:`TrapezoidProfile` is the 1-D law (accelerate at ``a_max``, cruise at the peak speed,
decelerate at ``a_max``); :class:`SyncJointProfile` drives all joints of a ``joint_move``
along one such law so that they start and arrive together.

Units: the 1-D profile is unit-agnostic as long as they agree — rad, rad/s, rad/s² for a joint,
mm, mm/s, mm/s² (or m) for a Cartesian path, 1, 1/s, 1/s² for a normalised path parameter.
Time is always in seconds, measured from the start of the move.
"""
from __future__ import annotations

import math
from typing import Optional, Union

import numpy as np

ArrayLike = Union[float, np.ndarray]

# A requested duration this little shorter than the minimum is float noise, not a request to
# go faster: accept it as the minimum.
_DURATION_RTOL = 1e-9


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} is {value:g}, expected a finite value > 0")
    return value


def _duration(value: Optional[float]) -> Optional[float]:
    if value is None:
        return None
    value = float(value)
    if not math.isfinite(value) or value < 0.0:
        raise ValueError(f"duration is {value:g} s, expected a finite value ≥ 0")
    return value


class TrapezoidProfile:
    """Move from 0 to ``distance`` (≥ 0) in minimum time with ``|v| ≤ v_max``, ``|a| ≤ a_max``,
    at rest at both ends; triangular (no cruise) when the distance is too short to reach
    ``v_max``.

    With ``duration`` (s) the move is stretched to take exactly that long: same shape, same
    ``a_max``, a lower cruise speed (the smaller root of ``v (T - v/a) = distance``). A
    duration shorter than the minimum raises :class:`ValueError`. ``distance = 0`` gives a
    profile that stays at 0 for ``duration`` (0 s by default). (Subnormal distances, below
    2.2e-308, arrive but may lose monotonicity by an ulp to rounding.)

    Attributes: ``distance``, ``v_max``, ``a_max``, ``min_duration`` (the time-optimal
    duration, s), ``duration`` (s), ``peak_speed`` (reached cruise speed, ≤ v_max),
    ``accel_time`` (length of each ramp, s).
    """

    def __init__(self, distance: float, v_max: float, a_max: float,
                 duration: Optional[float] = None):
        distance = float(distance)
        if not math.isfinite(distance) or distance < 0.0:
            raise ValueError(f"distance is {distance:g}, expected a finite value ≥ 0")
        self.distance = distance
        self.v_max = _positive("v_max", v_max)
        self.a_max = _positive("a_max", a_max)
        requested = _duration(duration)

        d, v, a = distance, self.v_max, self.a_max
        if d * a <= v * v:                        # triangular: v_max is never reached
            ramp = math.sqrt(d / a)
            peak = a * ramp                       # not sqrt(d a): that underflows first
            self.min_duration = 2.0 * ramp
        else:
            peak = v
            ramp = v / a
            self.min_duration = 2.0 * ramp + (d - v * ramp) / v

        if requested is not None and requested > self.min_duration:
            T = requested
            # Smaller root of v² / a - v T + d = 0, written without the cancellation of
            # (aT - sqrt(a²T² - 4ad)) / 2 so that tiny distances stay accurate.
            peak = 2.0 * d / (T + math.sqrt(max(T * T - 4.0 * d / a, 0.0)))
            ramp = peak / a
        elif requested is not None and requested < self.min_duration * (1.0 - _DURATION_RTOL):
            raise ValueError(f"duration {requested:.4f} s is shorter than the "
                             f"{self.min_duration:.4f} s needed to cover {d:g} at "
                             f"v_max {v:g} and a_max {a:g}")
        else:
            T = self.min_duration
        self.duration = T
        self.peak_speed = peak
        self.accel_time = ramp

    def sample(self, t: ArrayLike):
        """Position, speed and acceleration ``(s, v, a)`` at time ``t`` (s; scalar or array).

        Before the start the profile is at 0, after the end at ``distance``, both at rest
        (acceleration 0). Arrays in, arrays of the same shape out; scalar in, floats out.
        """
        t = np.asarray(t, dtype=float)
        T, ramp, peak, a, d = (self.duration, self.accel_time, self.peak_speed, self.a_max,
                               self.distance)
        tc = np.clip(t, 0.0, T)
        to_go = T - tc
        rising = tc < ramp
        falling = ~rising & (to_go < ramp)
        s = np.where(rising, 0.5 * a * tc * tc,
                     np.where(falling, d - 0.5 * a * to_go * to_go,
                              0.5 * a * ramp * ramp + peak * (tc - ramp)))
        v = np.where(rising, a * tc, np.where(falling, a * to_go, peak))
        acc = np.where(rising, a, np.where(falling, -a, 0.0))
        outside = (t < 0.0) | (t >= T)
        v = np.where(outside, 0.0, v)
        acc = np.where(outside, 0.0, acc)
        # Rounding must never carry the path past its ends, and the end is the end even when
        # the ramps underflow (subnormal distances).
        s = np.where(t >= T, d, np.clip(s, 0.0, d))
        if t.ndim == 0:
            return float(s), float(v), float(acc)
        return s, v, acc


def _joint_vector(name: str, value, n: Optional[int] = None) -> np.ndarray:
    vec = np.asarray(value, dtype=float)
    if vec.ndim != 1 or (n is not None and vec.shape[0] != n):
        expected = f"{n}" if n is not None else "a 1-D array of"
        raise ValueError(f"{name} has shape {vec.shape}, expected {expected} values")
    if not np.all(np.isfinite(vec)):
        raise ValueError(f"{name} contains NaN or inf: {vec.tolist()}")
    return vec


def _joint_limits(name: str, value, n: int) -> np.ndarray:
    vec = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy() \
        if np.ndim(value) == 0 else _joint_vector(name, value, n)
    bad = ~np.isfinite(vec) | (vec <= 0.0)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"{name} of joint_{i + 1} is {vec[i]:g}, expected a finite value > 0")
    return vec


class SyncJointProfile:
    """Synchronised point-to-point joint move (``joint_move``): every joint starts and arrives
    at the same time and the joint-space path is a straight line.

    All joints follow one normalised time law ``s(t)`` from 0 to 1:
    ``q(t) = q_start + s(t) (q_goal - q_start)``. Joint ``i`` then moves at ``|Δq_i| ṡ`` and
    accelerates at ``|Δq_i| s̈``, so its limits bound the law by ``v_max[i] / |Δq_i|`` and
    ``a_max[i] / |Δq_i|``; the law is the time-optimal trapezoid under the tightest of these
    bounds. (Stretching the slowest joint's own trapezoid onto the others is not enough: a
    joint that is slow because of its speed limit can impose an acceleration another joint
    cannot follow.) The joint whose bound is active is ``limiting_joint``.

    ``q_start``, ``q_goal``: rad, one value per joint. ``v_max`` (rad/s) and ``a_max`` (rad/s²):
    per joint or one value for all, > 0. ``duration`` (s): stretch the move to take exactly that
    long; shorter than ``predicted_duration`` raises :class:`ValueError`.

    Attributes: ``duration`` (s), ``predicted_duration`` (s, the time-optimal duration at these
    limits; equals ``duration`` unless stretched), ``peak_velocity`` and
    ``peak_acceleration`` (per joint, absolute, rad/s and rad/s²), ``limiting_joint`` (index,
    None when no joint moves), ``law`` (the normalised :class:`TrapezoidProfile`). A move too
    small for float to express against the limits (subnormal offsets) counts as no move: it
    takes 0 s and every sample is ``q_goal``.
    """

    def __init__(self, q_start, q_goal, v_max, a_max, duration: Optional[float] = None):
        self.q_start = _joint_vector("q_start", q_start)
        n = self.q_start.shape[0]
        self.q_goal = _joint_vector("q_goal", q_goal, n)
        self.v_max = _joint_limits("v_max", v_max, n)
        self.a_max = _joint_limits("a_max", a_max, n)
        requested = _duration(duration)
        self.delta = self.q_goal - self.q_start
        travel = np.abs(self.delta)

        with np.errstate(divide="ignore", over="ignore"):
            speed_bound = np.where(travel > 0, self.v_max / np.where(travel > 0, travel, 1.0),
                                   np.inf)
            accel_bound = np.where(travel > 0, self.a_max / np.where(travel > 0, travel, 1.0),
                                   np.inf)
        V, A = float(np.min(speed_bound)), float(np.min(accel_bound))
        # Infinite bounds: nothing moves (or by less than float can express against the limits).
        self.moving = math.isfinite(V) and math.isfinite(A)
        if self.moving:
            fastest = TrapezoidProfile(1.0, V, A)
            cruises = fastest.peak_speed >= V
            self.limiting_joint: Optional[int] = int(np.argmin(speed_bound if cruises
                                                               else accel_bound))
        else:
            fastest = TrapezoidProfile(0.0, 1.0, 1.0)
            self.limiting_joint = None
        self.predicted_duration = fastest.duration

        if requested is None:
            self.law = fastest
        else:
            if requested < self.predicted_duration * (1.0 - _DURATION_RTOL):
                k = self.limiting_joint
                raise ValueError(
                    f"requested duration {requested:.3f} s is shorter than the "
                    f"{self.predicted_duration:.3f} s this move needs (joint_{k + 1} moves "
                    f"{travel[k]:.3f} rad at most {self.v_max[k]:.2f} rad/s, "
                    f"{self.a_max[k]:.2f} rad/s²)")
            self.law = TrapezoidProfile(fastest.distance, fastest.v_max, fastest.a_max,
                                        duration=max(requested, self.predicted_duration))
        self.duration = self.law.duration
        scale = travel if self.moving else np.zeros(n)
        self.peak_velocity = scale * self.law.peak_speed
        self.peak_acceleration = scale * self.law.a_max if self.law.accel_time > 0 \
            else np.zeros(n)

    def sample(self, t: ArrayLike):
        """Joint position, velocity and acceleration ``(q, qd, qdd)`` at time ``t`` (s).

        Scalar ``t``: three arrays of shape (n,). Array ``t`` of shape (N,): shape (N, n).
        Clamped: ``q_start`` before the start, exactly ``q_goal`` from ``duration`` on.
        """
        t = np.asarray(t, dtype=float)
        s, sd, sdd = (np.asarray(x)[..., None] for x in self.law.sample(t))
        q = np.where(t[..., None] >= self.duration, self.q_goal, self.q_start + s * self.delta)
        return q, sd * self.delta, sdd * self.delta


def joint_move_profile(q_start, q_goal, v_max, a_max,
                       duration: Optional[float] = None) -> SyncJointProfile:
    """The :class:`SyncJointProfile` a backend plays for a joint move the driver planned to take
    ``duration`` s (``None``: the fastest). The driver planned from where the arm stood when the
    request came; a backend starts from where it drives the arm now, a tracking error away, so
    a ``duration`` that this start would need a little more than is taken as the fastest
    instead of refused (a request's ``mvtime`` that is too short was refused at the door)."""
    fastest = SyncJointProfile(q_start, q_goal, v_max, a_max)
    if duration is None or duration <= fastest.duration:
        return fastest
    return SyncJointProfile(q_start, q_goal, v_max, a_max, duration=duration)
