"""The closed-form IK of the Zu structure: up to 8 joint solutions of the ideal chain, in Python.

19 of the 22 JAKA arms (Zu, C, Pro, S, A5, and the A20 on the Zu 20's chain) are UR-type: three
parallel axes J2–J4, wrist axes J5 ⟂ J4, J6 ⟂ J5, so the solutions of the ideal geometry have a
closed form. :func:`zu_geometry` reads each model's ideal chain (its own lengths and shoulder,
and the constant turn of its joint-6 frame) from the joint axes; JAKA's files are not exactly
ideal (rpy written as 1.5708, sub-mm offsets, the A5's 1e-4 rad tilt): the caller finishes the
chosen solution with Newton steps on the exact model (:mod:`.numeric`). ``jaka_ik.c`` beside
this file is the same algorithm compiled, for the seeded fast path (:mod:`.native`).

Units and frames: m, rad; every pose is the 4x4 pose of the joint-6 frame in the base frame
(``base_link``); the shoulder is the ideal J1 frame's origin in the base.
"""
from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np

from .chain import axes_at_zero, joint_frames

_TWO_PI = 2.0 * math.pi
_RX = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])   # Rx(+π/2)
# Joint directions at q = 0 of the Zu structure (base frame): J1 up, J2–J4 and J6 along -y,
# J5 down — the same in all 19 of JAKA's Zu-like files, whatever their link frames.
_ZU_DIRECTIONS = np.array([[0, 0, 1], [0, -1, 0], [0, -1, 0], [0, -1, 0], [0, 0, -1], [0, -1, 0]],
                          float)
# How far a file may depart from the ideal Zu chain (m, rad): JAKA's sub-mm offsets and its
# 1.5708 for π/2 pass, anything structural does not. The Newton polish removes what passes;
# the closed form keeps solutions up to this far beyond a joint limit or the reach, for the
# polish to decide. Also in jaka_ik.c.
_SLACK = 2e-3


class ZuGeometry(NamedTuple):
    """The ideal Zu chain closest to a model's: ``lengths`` (a2, a3, d4, d5, d6) m, the
    ``shoulder`` (J1 axis at the height of J2, base frame, m), and ``tip``: the constant 4x4
    taking the model's joint-6 frame to the ideal chain's (identity for most files; the S7's
    flange is turned 180° about z). The ideal chain: J1 about z at the shoulder; J2 turned
    Rx(π/2); J3 at (a2, 0, 0); J4 at (a3, 0, -d4); J5 at (0, -d5, 0) turned Rx(π/2); J6 at
    (0, d6, 0) turned Rx(-π/2), each joint's own frame."""

    lengths: tuple[float, float, float, float, float]
    shoulder: tuple[float, float, float]
    tip: np.ndarray


def _ideal_joint6(lengths, shoulder, q) -> np.ndarray:
    """Joint-6 pose (4x4, base frame) of the ideal chain at ``q`` (rad)."""
    a2, a3, d4, d5, d6 = lengths
    places = ((np.eye(3), shoulder), (_RX, (0, 0, 0)), (np.eye(3), (a2, 0, 0)),
              (np.eye(3), (a3, 0, -d4)), (_RX, (0, -d5, 0)), (_RX.T, (0, d6, 0)))
    T = np.eye(4)
    for (R, t), qi in zip(places, q):
        P = np.eye(4)
        c, s = math.cos(qi), math.sin(qi)
        P[:3, :3] = R @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        P[:3, 3] = t
        T = T @ P
    return T


def zu_geometry(chain) -> ZuGeometry | None:
    """The ideal Zu chain of ``chain`` (:attr:`RobotModel.chain`), read from its joint axes at
    q = 0 and checked on random joint positions; None if the chain is not of the Zu
    structure (within :data:`_SLACK`)."""
    axes, flange = axes_at_zero(chain)
    if len(axes) != 6 or any(float(a.direction @ d) < math.cos(_SLACK)
                             for a, d in zip(axes, _ZU_DIRECTIONS)):
        return None
    (p1, p2, p3, p4, p5, p6) = (a.point for a in axes)
    sx, sy = p1[0], p1[1]
    d1 = p2[2]
    # each joint's axis where the ideal chain has it: J2 through J1, J3/J4 at J2's height,
    # J5 through J4's line, J6 through J5's, the flange on J6's
    if max(abs(p2[0] - sx), abs(p3[2] - d1), abs(p4[2] - d1), abs(p5[0] - p4[0]),
           abs(p6[0] - p5[0]), abs(flange[0, 3] - p6[0]), abs(flange[2, 3] - p6[2])) > _SLACK:
        return None
    lengths = (p3[0] - p2[0], p4[0] - p3[0], p5[1] - sy, p4[2] - p6[2], p5[1] - flange[1, 3])
    shoulder = (sx, sy, d1)
    joint6 = joint_frames(chain, np.zeros(6))[0][5]
    # What the tip fixes is a file's choice of frame (the S7's turn by π), exact; JAKA's
    # sub-mm departures from the ideal chain depend on the configuration and are left to the
    # polish, so the tip is rounded to a signed permutation without a translation.
    tip = np.eye(4)
    tip[:3, :3] = np.round((np.linalg.inv(joint6) @ _ideal_joint6(lengths, shoulder,
                                                                   np.zeros(6)))[:3, :3])
    for q in np.random.default_rng(0).uniform(-math.pi, math.pi, (8, 6)):
        E = np.linalg.inv(joint_frames(chain, q)[0][5] @ tip) @ _ideal_joint6(lengths,
                                                                               shoulder, q)
        if np.max(np.abs(E[:3, 3])) > _SLACK or np.max(np.abs(E[:3, :3] - np.eye(3))) > _SLACK:
            return None     # same lines at zero, but the joints or the flange turn otherwise
    return ZuGeometry(tuple(float(x) for x in lengths), tuple(float(x) for x in shoulder), tip)


class ClosedForm:
    """Closed-form solutions of one Zu-structure chain (see :func:`zu_geometry`).

    ``geometry`` the ideal chain (:class:`ZuGeometry`); ``lower``/``upper`` joint limits, rad;
    ``weight2`` the per-joint weight (1 / max_velocity)², (s/rad)², of the distance between
    configurations; ``joint_names`` name the joints in failure messages.
    """

    def __init__(self, geometry: ZuGeometry, lower: Sequence[float], upper: Sequence[float],
                 weight2: Sequence[float], joint_names: Sequence[str]):
        self.lengths = geometry.lengths
        self.shoulder = geometry.shoulder
        self._tip = None if np.array_equal(geometry.tip, np.eye(4)) else geometry.tip
        a2, a3 = geometry.lengths[:2]
        # cos q3 moves by |wrist - shoulder| · ε / (a2·a3) when the wrist moves by ε
        self._c3_slack = _SLACK * (a2 + a3) / (a2 * a3)
        # Plain floats, not numpy: for 8 small solutions the interpreter is faster than numpy's
        # per-call overhead, and this is the hot path of every seeded IK in Python.
        self._lower = [float(x) for x in lower]
        self._upper = [float(x) for x in upper]
        self._weight2 = [float(x) for x in weight2]
        self._joint_names = tuple(joint_names)

    def solutions(self, T: np.ndarray, ref: list[float], nearest_only: bool = False
                  ) -> tuple[list, str]:
        """Closed-form solutions for the joint-6 pose ``T`` (4x4, m, in the base frame; the
        model's own joint-6 frame, turned into the ideal chain's here).

        Returns ``([(distance, q), ...] nearest first, reason-if-none)``, q in rad. Each joint
        is taken at the 2π-turn nearest to ``ref`` (rad) and moved a turn into its limits if
        needed; solutions outside the limits are dropped. Distance = Σ ((q - ref) /
        max_velocity)², s². ``nearest_only`` skips branches that cannot beat the nearest one
        found so far (the list then starts with the nearest solution but may miss others).

        Derivation for the ideal chain (origin on the shoulder, x1/y1 = joint-1 frame axes after
        turning by q1): the joint-5 centre p5 = p - d6·z6 lies d4 off the arm plane along y1,
        which fixes q1 (2 ways); z6·y1 = -cos q5 (2 ways); q6 follows from x6·y1 = -sin q5 cos q6
        and y6·y1 = sin q5 sin q6; y4 = sin q6·x6 + cos q6·y6 gives q2+q3+q4; the planar 2R elbow
        (a2, a3) reaching p4 = p5 + d5·y4 gives q3 (2 ways) and q2.
        """
        a2, a3, d4, d5, d6 = self.lengths
        if self._tip is not None:
            T = T @ self._tip
        (xx, yx, zx, px), (xy, yy, zy, py), (xz, yz, zz, pz) = T[:3].tolist()
        ox, oy, oz = self.shoulder
        p5x, p5y, p5z = px - ox - d6 * zx, py - oy - d6 * zy, pz - oz - d6 * zz
        r = math.hypot(p5x, p5y)
        # Slack for the file's departures from the ideal chain; the polish decides there.
        if r < d4 - _SLACK:
            return [], "target out of reach: wrist centre too close to the joint-1 axis"
        lo, hi, w2 = self._lower, self._upper, self._weight2
        r1, r2, r3, r4, r5, r6 = ref
        pi, two_pi = math.pi, _TWO_PI
        bad = [0] * 6

        def near(x: float, j: int, r: float) -> float | None:
            # the turn nearest r, else the one a turn away; a turn outside the limits by no
            # more than the ideal chain's error is put on the limit
            v = r + (x - r + pi) % two_pi - pi
            for w in (v, v - two_pi if v > r else v + two_pi):
                if lo[j] - _SLACK <= w <= hi[j] + _SLACK:
                    return min(hi[j], max(lo[j], w))
            bad[j] += 1
            return None

        phi = math.atan2(p5y, p5x)
        alpha = math.asin(min(d4 / r, 1.0))
        out = []
        best = math.inf  # with nearest_only, subtrees already farther than this are skipped
        reach = False
        shoulders = []
        for q1 in (phi - alpha, phi + alpha - pi):
            v1 = near(q1, 0, r1)
            if v1 is not None:
                shoulders.append((w2[0] * (v1 - r1) ** 2, q1, v1))
        shoulders.sort()
        for dist1, q1, v1 in shoulders:
            if dist1 >= best:
                break
            c1, s1 = math.cos(q1), math.sin(q1)
            c5 = min(1.0, max(-1.0, s1 * zx - c1 * zy))
            xy1, yy1 = c1 * xy - s1 * xx, c1 * yy - s1 * yx
            q5a = math.acos(c5)
            wrists = []
            for q5 in ((q5a, -q5a) if q5a > 1e-12 else (0.0,)):
                s5 = math.sin(q5)
                # At sin q5 = 0 the J6 axis is parallel to J2..J4 and only q4 ± q6 is defined:
                # keep the reference q6. The slack covers the URDF's departures from the ideal
                # chain, which leave sin q5 ~ 1e-5 at a truly singular pose.
                q6 = (math.atan2(yy1, -xy1) if s5 > 1e-4 else
                      math.atan2(-yy1, xy1) if s5 < -1e-4 else r6)
                v5, v6 = near(q5, 4, r5), near(q6, 5, r6)
                if v5 is not None and v6 is not None:
                    wrists.append((dist1 + w2[4] * (v5 - r5) ** 2 + w2[5] * (v6 - r6) ** 2,
                                   q6, v5, v6))
            wrists.sort()
            for dist56, q6, v5, v6 in wrists:
                if dist56 >= best:
                    break
                c6, s6 = math.cos(q6), math.sin(q6)
                y4x, y4y, y4z = s6 * xx + c6 * yx, s6 * xy + c6 * yy, s6 * xz + c6 * yz
                q234 = math.atan2(-(c1 * y4x + s1 * y4y), y4z)
                u = c1 * (p5x + d5 * y4x) + s1 * (p5y + d5 * y4y)
                v = p5z + d5 * y4z
                c3 = (u * u + v * v - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
                if abs(c3) > 1.0 + self._c3_slack:
                    continue
                reach = True
                q3a = math.acos(min(1.0, max(-1.0, c3)))
                for q3 in ((q3a, -q3a) if q3a > 1e-12 else (0.0,)):
                    q2 = math.atan2(v, u) - math.atan2(a3 * math.sin(q3), a2 + a3 * c3)
                    v2, v3, v4 = near(q2, 1, r2), near(q3, 2, r3), near(q234 - q2 - q3, 3, r4)
                    if v2 is None or v3 is None or v4 is None:
                        continue
                    dist = (dist56 + w2[1] * (v2 - r2) ** 2 + w2[2] * (v3 - r3) ** 2
                            + w2[3] * (v4 - r4) ** 2)
                    out.append((dist, (v1, v2, v3, v4, v5, v6)))
                    if nearest_only and dist < best:
                        best = dist
        if out:
            out.sort(key=lambda s: s[0])
            return out, ""
        if not reach and not any(bad[1:4]) and not bad[0]:
            return [], "target out of reach: beyond the elbow's range"
        names = ", ".join(n for n, b in zip(self._joint_names, bad) if b)
        return [], f"every IK solution violates joint limits ({names})"
