"""Time-based interpolation of a joint trajectory's waypoints, as joint_trajectory_controller
does it: per segment a quintic when both ends give velocities and accelerations, a cubic when
they give velocities, else linear. Units: s, rad, rad/s, rad/s².
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .trajectory import time_grid


@dataclass(frozen=True)
class Waypoint:
    """A trajectory point at ``time`` s after the start, with optional velocity/acceleration."""

    time: float
    q: np.ndarray
    qd: Optional[np.ndarray] = None
    qdd: Optional[np.ndarray] = None


def _coefficients(p0, v0, a0, p1, v1, a1, T):
    """Quintic coefficients c0…c5 (each an array over joints) matching both ends."""
    T2, T3, T4, T5 = T * T, T ** 3, T ** 4, T ** 5
    c0, c1, c2 = p0, v0, a0 / 2.0
    c3 = (20 * (p1 - p0) - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T2) / (2 * T3)
    c4 = (30 * (p0 - p1) + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T2) / (2 * T4)
    c5 = (12 * (p1 - p0) - 6 * (v1 + v0) * T - (a0 - a1) * T2) / (2 * T5)
    return np.stack([c0, c1, c2, c3, c4, c5])


def _cubic(p0, v0, p1, v1, T):
    zero = np.zeros_like(p0)
    c2 = (3 * (p1 - p0) - (2 * v0 + v1) * T) / T ** 2
    c3 = (2 * (p0 - p1) + (v0 + v1) * T) / T ** 3
    return np.stack([p0, v0, c2, c3, zero, zero])


def sample_waypoints(start_q: np.ndarray, points: list[Waypoint], cycle: float):
    """Sample the trajectory from ``start_q`` at t = 0 through ``points`` every ``cycle`` s.

    The segment from the start to the first point uses zero start velocity (the arm is at
    rest). Returns ``(times (N,), q (N, 6), qd (N, 6))``.
    """
    first = Waypoint(0.0, np.asarray(start_q, float), np.zeros(len(start_q)),
                     np.zeros(len(start_q)))
    if points and points[0].time == 0.0:
        chain = points
    else:
        chain = [first] + list(points)
    times = time_grid(chain[-1].time, cycle)
    q = np.empty((len(times), len(start_q)))
    qd = np.empty_like(q)
    seg_starts = np.array([p.time for p in chain])
    seg = np.clip(np.searchsorted(seg_starts, times, side="right") - 1, 0, len(chain) - 2)
    for k in range(len(chain) - 1):
        a, b = chain[k], chain[k + 1]
        T = b.time - a.time
        mask = seg == k
        if not mask.any():
            continue
        tau = (times[mask] - a.time)[:, None]
        if a.qd is not None and b.qd is not None:
            if a.qdd is not None and b.qdd is not None:
                c = _coefficients(a.q, a.qd, a.qdd, b.q, b.qd, b.qdd, T)
            else:
                c = _cubic(a.q, a.qd, b.q, b.qd, T)
            powers = np.stack([tau ** i for i in range(6)])            # (6, n, 1)
            q[mask] = np.sum(c[:, None, :] * powers, axis=0)
            dpowers = np.stack([i * tau ** max(i - 1, 0) for i in range(6)])
            qd[mask] = np.sum(c[:, None, :] * dpowers, axis=0)
        else:
            s = tau / T
            q[mask] = a.q + s * (b.q - a.q)
            qd[mask] = np.broadcast_to((b.q - a.q) / T, (int(mask.sum()), len(start_q)))
    q[-1], qd[-1] = chain[-1].q, (chain[-1].qd if chain[-1].qd is not None else 0.0)
    return times, q, qd
