"""The closed-form IK of a UR-type arm: up to 8 joint solutions of the ideal chain, in Python.

The Zu arms are UR-type (three parallel axes J2–J4, wrist axes J5 ⟂ J4, J6 ⟂ J5), so the
solutions of the ideal geometry have a closed form. The official URDFs are not exactly ideal
(rpy written as 1.5708, a 1.2e-5 m offset in joint_4's origin): the caller finishes the chosen
solution with Newton steps on the exact model (:mod:`.numeric`). ``jaka_ik.c`` beside this file
is the same algorithm compiled, for the seeded fast path (:mod:`.native`).

Units and frames: m, rad; every pose is the 4x4 pose of the joint-6 frame in the base frame
(``base_link``); the shoulder is the joint-1 frame origin in the base.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import pinocchio as pin

_TWO_PI = 2.0 * math.pi


def ur_lengths(model: pin.Model) -> tuple[float, float, float, float, float] | None:
    """(a2, a3, d4, d5, d6) in m if the 6-joint chain has the UR-type layout the closed form
    assumes, else None.

    Small deviations (up to 1e-3 m / rad) are accepted: the Newton polish removes them.
    """
    jp = [model.jointPlacements[i] for i in range(1, 7)]
    rx = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float)  # Rx(+pi/2)
    want_R = [np.eye(3), rx, np.eye(3), np.eye(3), rx, rx.T]
    if any(not np.allclose(p.rotation, R, atol=1e-3) for p, R in zip(jp[1:], want_R[1:])):
        return None
    t = [p.translation for p in jp]
    a2, a3, d4, d5, d6 = t[2][0], t[3][0], -t[3][2], -t[4][1], t[5][1]
    off = [t[1], (0, t[2][1], t[2][2]), (0, t[3][1], 0), (t[4][0], 0, t[4][2]),
           (t[5][0], 0, t[5][2])]
    if np.max(np.abs(np.array(off, float))) > 1e-3 or not np.allclose(jp[0].rotation, np.eye(3)):
        return None
    return float(a2), float(a3), float(d4), float(d5), float(d6)


class ClosedForm:
    """Closed-form solutions of one UR-type chain (see :func:`ur_lengths`).

    ``lengths`` (a2, a3, d4, d5, d6) m; ``shoulder`` the joint-1 frame origin in the base, m
    (its rotation is identity); ``lower``/``upper`` joint limits, rad; ``weight2`` the per-joint
    weight (1 / max_velocity)², (s/rad)², of the distance between configurations;
    ``joint_names`` name the joints in failure messages.
    """

    def __init__(self, lengths: Sequence[float], shoulder: Sequence[float],
                 lower: Sequence[float], upper: Sequence[float], weight2: Sequence[float],
                 joint_names: Sequence[str]):
        self.lengths = tuple(float(x) for x in lengths)
        self.shoulder = tuple(float(x) for x in shoulder)
        # Plain floats, not numpy: for 8 small solutions the interpreter is faster than numpy's
        # per-call overhead, and this is the hot path of every seeded IK in Python.
        self._lower = [float(x) for x in lower]
        self._upper = [float(x) for x in upper]
        self._weight2 = [float(x) for x in weight2]
        self._joint_names = tuple(joint_names)

    def solutions(self, T: np.ndarray, ref: list[float], nearest_only: bool = False
                  ) -> tuple[list, str]:
        """Closed-form solutions for the joint-6 pose ``T`` (4x4, m, in the base frame).

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
        (xx, yx, zx, px), (xy, yy, zy, py), (xz, yz, zz, pz) = T[:3].tolist()
        ox, oy, oz = self.shoulder
        p5x, p5y, p5z = px - ox - d6 * zx, py - oy - d6 * zy, pz - oz - d6 * zz
        r = math.hypot(p5x, p5y)
        # Slack for the URDF's departures from the ideal chain; the polish decides there.
        if r < d4 * (1.0 - 1e-4):
            return [], "target out of reach: wrist centre too close to the joint-1 axis"
        lo, hi, w2 = self._lower, self._upper, self._weight2
        r1, r2, r3, r4, r5, r6 = ref
        pi, two_pi = math.pi, _TWO_PI
        bad = [0] * 6

        def near(x: float, j: int, r: float) -> float | None:
            v = r + (x - r + pi) % two_pi - pi
            if v > hi[j]:
                v -= two_pi
            elif v < lo[j]:
                v += two_pi
            if lo[j] <= v <= hi[j]:
                return v
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
                if abs(c3) > 1.0 + 1e-4:
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
