"""The closed-form IK of an arm with a spherical wrist (the JAKA MiniCobo): up to 8 solutions of
the ideal chain.

J4, J5 and J6 cross at one point, the wrist centre, which the flange carries a fixed distance
along J6: the target places it, and J1 … J3 reach it (:class:`.arm_plane.ArmPlane`, 4 ways);
the wrist then turns the rest as three Euler angles about J4, J5, J6 (2 ways: J5 one side or
the other). JAKA's file is not exactly ideal (π/2 written 1.5708): the caller finishes the
chosen solution with Newton steps on the exact model (:mod:`.numeric`).

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

SLACK = 2e-3    # m, rad: the file's departure from the ideal chain (as closed_form._SLACK)


class SphericalWrist:
    """The solutions of one spherical-wrist chain; build with :meth:`fit`."""

    def __init__(self, plane: ArmPlane, axes: Sequence[np.ndarray], centre_in_j6: np.ndarray,
                 zero_j6: np.ndarray, branches: Branches):
        self._plane = plane
        self._u4, self._u5, self._u6 = axes
        self._sign46 = float(self._u4 @ self._u6)     # J4 and J6 along or against each other
        self._centre = centre_in_j6                 # wrist centre in the joint-6 frame
        self._zero_R = zero_j6[:3, :3]              # joint-6 frame's rotation at q = 0
        self._branches = branches

    @staticmethod
    def fit(chain, branches: Branches) -> "SphericalWrist | None":
        """The ideal chain of ``chain`` (:attr:`RobotModel.chain`), or None unless J4, J5 and
        J6 cross at one point (within :data:`SLACK`) with J5 across J4 and J6, and J1 … J3
        lie as :class:`ArmPlane` needs."""
        axes, _ = axes_at_zero(chain)
        if len(axes) != 6:
            return None
        a45, b45 = closest_points(axes[3], axes[4])
        a56, b56 = closest_points(axes[4], axes[5])
        centre = (a45 + b45 + a56 + b56) / 4.0
        if max(np.linalg.norm(p - centre) for p in (a45, b45, a56, b56)) > SLACK:
            return None
        u4, u5, u6 = (snapped(a.direction) for a in axes[3:])
        if abs(u4 @ u6) != 1.0 or abs(u4 @ u5) > SLACK:
            return None
        plane = ArmPlane.fit(axes, centre)
        if plane is None:
            return None
        j6 = joint_frames(chain, np.zeros(6))[0][5]
        centre_in_j6 = j6[:3, :3].T @ (centre - j6[:3, 3])
        return SphericalWrist(plane, (u4, u5, u6), centre_in_j6, j6, branches)

    def solutions(self, T: np.ndarray, ref: Sequence[float], nearest_only: bool = False
                  ) -> tuple[list, str]:
        """Solutions for the joint-6 pose ``T`` (4x4, m, base frame), as
        ``ClosedForm.solutions``: ``([(distance s², q rad), ...] nearest first, reason)``.
        ``nearest_only`` is accepted for the same interface; all 8 are cheap here."""
        centre = T[:3, :3] @ self._centre + T[:3, 3]
        q123, valid = self._plane.place(centre[None, :], SLACK)
        # the wrist's own turn: R = R03 · e4 e5 e6 · R0 (product of exponentials)
        goal = T[:3, :3] @ self._zero_R.T
        raw = []
        for k in range(4):
            if not valid[0, k]:
                continue
            q1, q2, q3 = q123[0, k]
            Rw = self._plane.rotation((q1, q2, q3)).T @ goal
            raw += [(q1, q2, q3) + w for w in self._wrist(Rw, ref[5])]
        return self._branches.ordered(raw, ref, "target out of reach: the wrist centre is "
                                                "beyond the arm's reach")

    def _wrist(self, Rw: np.ndarray, ref6: float) -> list[tuple[float, float, float]]:
        """(q4, q5, q6) with e4·e5·e6 = ``Rw``, eᵢ the turn by qᵢ about uᵢ: 2 ways, or 1 at
        q5 = 0 (J4 and J6 in line), where J6 keeps its reference ``ref6``."""
        u4, u5, u6 = self._u4, self._u5, self._u6
        a = Rw @ u6
        c5 = max(-1.0, min(1.0, float(u4 @ a) * self._sign46))
        q5a = math.acos(c5)
        if math.sin(q5a) < 1e-6:
            q6 = ref6
            q4 = angle_about(u4, u5, Rw @ rotvec_to_matrix(u6 * -q6) @ u5)
            return [(q4, 0.0 if c5 > 0 else math.pi, q6)]
        out = []
        for q5 in (q5a, -q5a):
            e5 = rotvec_to_matrix(u5 * q5)
            q4 = angle_about(u4, e5 @ u6, a)
            e45 = rotvec_to_matrix(u4 * q4) @ e5
            q6 = angle_about(u6, u5, e45.T @ Rw @ u5)
            out.append((q4, q5, q6))
        return out
