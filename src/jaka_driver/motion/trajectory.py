"""The sampled joint motion every executor plays: one representation for joint_move,
linear_move and FollowJointTrajectory, so the twin runs them all the same way.

Units: time s from the start of the motion, joint positions rad, velocities rad/s, TCP poses
4x4 homogeneous matrices in metres (in the frame the planner was given).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

# The longest single motion the driver plans, s. A sampled motion of 10 min is 75 000 samples
# (~7 MB with velocities); far longer ones come only from units mistakes (mvvelo 1e-7) and would
# take gigabytes and minutes of planning that stop_move cannot interrupt.
MAX_MOTION_DURATION = 600.0


def time_grid(duration: float, cycle: float) -> np.ndarray:
    """Sample times (s) for a motion of ``duration`` s: every ``cycle`` s from 0, and the end
    itself. A remainder under half a cycle is merged into the last interval rather than left
    as a sliver: over a sliver, a planner's finite differences would turn solver noise into
    absurd speeds. ``duration = 0`` gives ``[0]``; a duration above
    :data:`MAX_MOTION_DURATION` raises :class:`ValueError` (callers name the request field
    before they get here; this is the guard on memory)."""
    duration, cycle = float(duration), float(cycle)
    if not math.isfinite(cycle) or cycle <= 0.0:
        raise ValueError(f"cycle is {cycle:g} s, expected a finite value > 0")
    if not math.isfinite(duration) or duration < 0.0:
        raise ValueError(f"duration is {duration:g} s, expected a finite value ≥ 0")
    if duration > MAX_MOTION_DURATION:
        raise ValueError(f"duration is {duration:.4g} s, above the limit of "
                         f"{MAX_MOTION_DURATION:g} s for one motion")
    if duration == 0.0:
        return np.zeros(1)
    full = int(math.floor(duration / cycle + 1e-9))
    times = np.arange(full + 1, dtype=float) * cycle
    if full >= 1 and duration - times[-1] < 0.5 * cycle:
        times[-1] = duration
    else:
        times = np.append(times, duration)
    return times


@dataclass
class JointTrajectory:
    """Joint positions ``q`` (N, n) rad and velocities ``qd`` (N, n) rad/s at ``times`` (N,) s,
    with ``times[0] = 0`` and strictly increasing. ``tcp`` (N, 4, 4), optional: the planned TCP
    pose of each sample (m), kept by Cartesian planners for checks and display."""

    times: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tcp: Optional[np.ndarray] = None

    def __post_init__(self):
        self.times = np.asarray(self.times, dtype=float)
        self.q = np.atleast_2d(np.asarray(self.q, dtype=float))
        self.qd = np.atleast_2d(np.asarray(self.qd, dtype=float))
        n_samples = self.times.shape[0]
        if self.times.ndim != 1 or n_samples == 0:
            raise ValueError(f"times has shape {self.times.shape}, expected (N,) with N ≥ 1")
        if self.times[0] != 0.0 or np.any(np.diff(self.times) <= 0.0):
            raise ValueError("times must start at 0 s and increase strictly")
        if self.q.shape[0] != n_samples or self.qd.shape != self.q.shape:
            raise ValueError(f"q {self.q.shape} and qd {self.qd.shape} must both be "
                             f"({n_samples}, n) for {n_samples} sample times")
        if self.tcp is not None:
            self.tcp = np.asarray(self.tcp, dtype=float)
            if self.tcp.shape != (n_samples, 4, 4):
                raise ValueError(f"tcp has shape {self.tcp.shape}, expected ({n_samples}, 4, 4)")

    @property
    def duration(self) -> float:
        """Time of the last sample, s (0 for a single-sample trajectory: already there)."""
        return float(self.times[-1])

    def sample(self, t):
        """``(q, qd)`` at time ``t`` (s): linear interpolation between samples, clamped to the
        first / last sample outside ``[0, duration]``. Scalar ``t`` gives arrays (n,), an
        array of N times gives (N, n)."""
        t = np.asarray(t, dtype=float)
        if self.times.shape[0] == 1:
            shape = t.shape + self.q.shape[1:]
            return (np.broadcast_to(self.q[0], shape).copy(),
                    np.broadcast_to(self.qd[0], shape).copy())
        tc = np.clip(t, 0.0, self.duration)
        k = np.clip(np.searchsorted(self.times, tc, side="right") - 1, 0,
                    self.times.shape[0] - 2)
        w = ((tc - self.times[k]) / (self.times[k + 1] - self.times[k]))[..., None]
        q = self.q[k] + w * (self.q[k + 1] - self.q[k])
        qd = self.qd[k] + w * (self.qd[k + 1] - self.qd[k])
        return q, qd

    def time_scaled(self, ratio: float) -> "JointTrajectory":
        """The same path played ``ratio`` (0 < ratio ≤ 1) times as fast: time × 1/ratio,
        velocities × ratio (accelerations × ratio²), resampled on the first interval's cycle
        (:func:`time_grid`) as the players expect. The planned TCP poses are not carried."""
        if not 0.0 < ratio <= 1.0:
            raise ValueError(f"ratio is {ratio:g}, expected in (0, 1]")
        if ratio == 1.0 or self.times.shape[0] == 1:
            return self
        times = time_grid(self.duration / ratio, float(self.times[1] - self.times[0]))
        q, qd = self.sample(times * ratio)
        return JointTrajectory(times=times, q=q, qd=qd * ratio)

    @classmethod
    def from_profile(cls, profile, cycle: float) -> "JointTrajectory":
        """Sample a joint profile (anything with ``duration`` s and ``sample(t) -> (q, qd, …)``,
        e.g. :class:`~jaka_driver.motion.profiles.SyncJointProfile`) on :func:`time_grid`."""
        times = time_grid(profile.duration, cycle)
        q, qd = profile.sample(times)[:2]
        return cls(times=times, q=q, qd=qd)
