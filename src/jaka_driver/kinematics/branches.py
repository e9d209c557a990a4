"""Choosing among IK solutions as a controller does: each joint at the 2π-turn nearest to a
reference, inside the joint limits, and the solutions ordered by their distance from the
reference in seconds of joint travel (Σ ((q - ref) / max_velocity)²).

Used by the solvers of the ideal chains that have no closed form of the Zu kind
(:mod:`.spherical_wrist`, :mod:`.forearm_roll`); :mod:`.closed_form` does the same inline, in
plain floats, on its hot path. Units: rad, s².
"""
from __future__ import annotations

import math
from typing import Sequence

_TWO_PI = 2.0 * math.pi


class Branches:
    """Limits (rad), weights (1 / max_velocity)² ((s/rad)²) and joint names of one arm;
    ``slack`` (rad): how far beyond a limit a solution of the ideal chain may lie and still be
    kept (on the limit), for the Newton polish on the exact chain to decide."""

    def __init__(self, lower: Sequence[float], upper: Sequence[float],
                 weight2: Sequence[float], joint_names: Sequence[str], slack: float):
        self.lower = [float(x) for x in lower]
        self.upper = [float(x) for x in upper]
        self.weight2 = [float(x) for x in weight2]
        self.joint_names = tuple(joint_names)
        self.slack = float(slack)

    def place(self, q: Sequence[float], ref: Sequence[float], bad: list[int]):
        """``(distance s², q)`` with every joint at the turn nearest to ``ref`` inside the
        limits (else the next turn; a turn beyond a limit by no more than ``slack`` is put on
        the limit), or None (counting the joints that could not be placed in ``bad``)."""
        out, dist = [], 0.0
        for j, (x, r) in enumerate(zip(q, ref)):
            v = r + (x - r + math.pi) % _TWO_PI - math.pi
            lo, hi = self.lower[j], self.upper[j]
            w = next((min(hi, max(lo, t)) for t in (v, v - _TWO_PI if v > r else v + _TWO_PI)
                      if lo - self.slack <= t <= hi + self.slack), None)
            if w is None:
                bad[j] += 1
                return None
            out.append(w)
            dist += self.weight2[j] * (w - r) ** 2
        return dist, tuple(out)

    def ordered(self, raw, ref: Sequence[float], reach_reason: str) -> tuple[list, str]:
        """The solutions ``raw`` (joint tuples, rad) placed and nearest first, as
        ``ClosedForm.solutions`` answers: ``([(distance, q), ...], reason-if-none)``."""
        bad = [0] * 6
        placed = [p for p in (self.place(q, ref, bad) for q in raw) if p is not None]
        if placed:
            placed.sort(key=lambda s: s[0])
            return placed, ""
        if not raw:
            return [], reach_reason
        names = ", ".join(n for n, b in zip(self.joint_names, bad) if b)
        return [], f"every IK solution violates joint limits ({names})"
