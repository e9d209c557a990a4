"""The IK of an arm with a forearm roll and an offset wrist (the JAKA A12): every solution of the
ideal chain, by a one-dimensional search.

J4 runs along the forearm and crosses J5 at the wrist point W; J5 crosses J6 at P, a fixed
distance ℓ from W along J5; the flange sits on J6. The target fixes P and J6's direction n;
J5 is across n, so its direction is u(θ) = cos θ·e1 + sin θ·e2 for some θ (e1, e2 across n),
and W = P - ℓ·u(θ). For each θ, J1 … J3 place W (:class:`.arm_plane.ArmPlane`, 4 ways), and
the solutions are where J4 — along the forearm, wherever J1 … J3 put it — is across u(θ).
That condition is searched on a grid of θ for every one of the 4 ways and each sign change
interpolated (where |J4 · u| dips towards 0 between samples, more finely: two roots may hide
there); J4 … J6 then follow in closed form. No closed form of this layout is known to
us, so each solution is exact only to the grid (~1e-3 rad): the caller finishes the chosen one
with Newton steps on the exact model (:mod:`.numeric`), as it does the other structures'.

Units and frames: m, rad; every pose is the 4x4 pose of the joint-6 frame in the base frame.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..common.transforms import rotvec_to_matrix
from .arm_plane import ArmPlane, angle_about
from .branches import Branches
from .chain import axes_at_zero, closest_points, joint_frames, snapped

SLACK = 2e-3                # m, rad: the file's departure from the ideal chain
GRID = 360                  # θ samples over a turn
FINE = 32                   # samples across two grid steps where two roots may hide


class ForearmRoll:
    """The solutions of one forearm-roll chain; build with :meth:`fit`."""

    def __init__(self, plane: ArmPlane, axes: Sequence[np.ndarray], offset: float,
                 p_in_j6: np.ndarray, zero_j6: np.ndarray, branches: Branches):
        self._plane = plane
        self._u4, self._u5, self._u6 = axes
        self._offset = offset               # ℓ: W → P along J5's direction, m
        self._p = p_in_j6                   # P in the joint-6 frame
        self._zero_R = zero_j6[:3, :3]
        self._branches = branches
        self._step = 2.0 * math.pi / GRID

    @staticmethod
    def fit(chain, branches: Branches) -> "ForearmRoll | None":
        """The ideal chain of ``chain``, or None unless J4 crosses J5 and J5 crosses J6 (at
        two points, within :data:`SLACK`), each across the other, and J1 … J3 lie as
        :class:`ArmPlane` needs."""
        axes, _ = axes_at_zero(chain)
        if len(axes) != 6:
            return None
        w, w5 = closest_points(axes[3], axes[4])
        p5, p = closest_points(axes[4], axes[5])
        if np.linalg.norm(w - w5) > SLACK or np.linalg.norm(p5 - p) > SLACK:
            return None
        u4, u5, u6 = (snapped(a.direction) for a in axes[3:])
        if abs(u4 @ u5) > SLACK or abs(u5 @ u6) > SLACK or abs(u4 @ u6) == 1.0:
            return None
        plane = ArmPlane.fit(axes, w)
        if plane is None:
            return None
        j6 = joint_frames(chain, np.zeros(6))[0][5]
        return ForearmRoll(plane, (u4, u5, u6), float((p - w) @ u5),
                           j6[:3, :3].T @ (p - j6[:3, 3]), j6, branches)

    def solutions(self, T: np.ndarray, ref: Sequence[float], nearest_only: bool = False
                  ) -> tuple[list, str]:
        """Solutions for the joint-6 pose ``T`` (4x4, m, base frame), as
        ``ClosedForm.solutions``: ``([(distance s², q rad), ...] nearest first, reason)``.
        ``nearest_only`` is accepted for the same interface: the search finds them all."""
        goal = T[:3, :3] @ self._zero_R.T           # e1 … e6 (product of exponentials)
        n = goal @ self._u6                          # J6's direction now
        p = T[:3, :3] @ self._p + T[:3, 3]
        e1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        basis = (e1, e2)
        theta = np.arange(GRID) * self._step
        f, valid = self._condition(theta, p, basis)
        roots = self._roots(theta, f, valid)
        # a pair of roots closer than the grid shows as a dip of |f| towards 0 with no sign
        # change on either side: look there again, finely (all such places in one batch)
        fp, fn = np.roll(f, 1, 0), np.roll(f, -1, 0)
        af = np.abs(f)
        dip = (valid & np.roll(valid, 1, 0) & np.roll(valid, -1, 0)
               & ((f > 0) == (fp > 0)) & ((f > 0) == (fn > 0))
               & (af <= np.abs(fp)) & (af <= np.abs(fn))
               & (af < 2.0 * np.maximum(np.abs(fp - f), np.abs(fn - f))))
        g, k = np.nonzero(dip)
        if len(g):
            fine = theta[g][:, None] + np.linspace(-1.0, 1.0, FINE + 1) * self._step
            ff, fv = self._condition(fine.ravel(), p, basis)
            ff = ff.reshape(len(g), FINE + 1, 4)[np.arange(len(g)), :, k]
            fv = fv.reshape(len(g), FINE + 1, 4)[np.arange(len(g)), :, k]
            change = fv[:, :-1] & fv[:, 1:] & ((ff[:, :-1] > 0) != (ff[:, 1:] > 0))
            i, j = np.nonzero(change)
            fa, fb = ff[i, j], ff[i, j + 1]
            t = fine[i, j] + fa / (fa - fb) * (fine[i, j + 1] - fine[i, j])
            roots += list(zip(t.tolist(), k[i].tolist()))
        raw = self._finish(roots, p, basis, n, goal)
        why = ("target out of reach: no arm configuration turns the flange this way here"
               if valid.any() else "target out of reach: the wrist cannot get there")
        return self._branches.ordered(raw, ref, why)

    def _condition(self, theta: np.ndarray, p: np.ndarray, basis) -> tuple[np.ndarray,
                                                                            np.ndarray]:
        """J4 · u(θ) for each θ (rad) and each of the 4 ways (``(len(θ), 4)``), and where the
        wrist point W(θ) is within reach (same shape)."""
        u = np.cos(theta)[:, None] * basis[0] + np.sin(theta)[:, None] * basis[1]
        q123, valid = self._plane.place(p - self._offset * u, SLACK)
        return np.einsum("gkc,gc->gk", self._plane.rotate(q123, self._u4), u), valid

    @staticmethod
    def _roots(theta: np.ndarray, f: np.ndarray, valid: np.ndarray) -> list[tuple[float, int]]:
        """(θ, way) of each sign change of ``f`` between neighbouring valid samples round the
        turn, θ interpolated linearly."""
        f_next, v_next = np.roll(f, -1, 0), np.roll(valid, -1, 0)
        g, k = np.nonzero(valid & v_next & ((f > 0) != (f_next > 0)))
        fa, fb = f[g, k], f_next[g, k]
        step = 2.0 * math.pi / len(theta)
        return list(zip((theta[g] + fa / (fa - fb) * step).tolist(), k.tolist()))

    def _finish(self, roots, p, basis, n, goal) -> list[tuple[float, ...]]:
        """The six joints at each root (θ, way): J1 … J3 placing W(θ), then J4 … J6."""
        if not roots:
            return []
        theta = np.array([t for t, _ in roots])
        ways = np.array([k for _, k in roots])
        u5 = np.cos(theta)[:, None] * basis[0] + np.sin(theta)[:, None] * basis[1]
        q123, valid = self._plane.place(p - self._offset * u5, SLACK)
        pick = np.arange(len(roots))
        q123, valid = q123[pick, ways], valid[pick, ways]
        return [tuple(q.tolist()) + self._wrist(q, u, n, goal)
                for q, u, ok in zip(q123, u5, valid) if ok]

    def _wrist(self, q123: np.ndarray, u5: np.ndarray, n: np.ndarray, goal: np.ndarray
               ) -> tuple[float, float, float]:
        """(q4, q5, q6) once J1 … J3 are at ``q123``, J5 along ``u5`` and J6 along ``n``."""
        R03 = self._plane.rotation(q123)
        q4 = angle_about(R03 @ self._u4, R03 @ self._u5, u5)
        R04 = R03 @ rotvec_to_matrix(self._u4 * q4)
        q5 = angle_about(self._u5, self._u6, R04.T @ n)
        R05 = R04 @ rotvec_to_matrix(self._u5 * q5)
        q6 = angle_about(self._u6, self._u5, R05.T @ goal @ self._u5)
        return q4, q5, q6
