"""The first three joints of a JAKA arm as a plane: J1 turns the arm plane about the vertical,
J2 and J3 (parallel, across the plane) fold it; a wrist point carried by J3's link stays a
fixed distance beside J1's axis. This places the wrist point (J1 … J3, up to 4 ways) and
turns directions through the three joints, for the arms whose wrist is not of the Zu kind
(:mod:`.spherical_wrist`, :mod:`.forearm_roll`).

Everything is read from the chain's axes at q = 0 (:mod:`.chain`) in the product-of-
exponentials sense: a joint turns what comes after it about its line at q = 0, so the link
frames JAKA's files choose do not matter. Coordinates in the arm plane at q1 = 0: radial = base
x, lateral = base y, up = base z. Units: m, rad; base frame.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..common.transforms import rotvec_to_matrix
from .chain import Axis, snapped

_Y = np.array([0.0, 1.0, 0.0])
_Z = np.array([0.0, 0.0, 1.0])


def angle_about(axis: np.ndarray, p: np.ndarray, q: np.ndarray) -> float:
    """The angle (rad) of the turn about the unit ``axis`` that takes ``p``'s direction round
    to ``q``'s (their parts across the axis). Plain floats: numpy's cross costs more than the
    arithmetic."""
    (ax, ay, az), (px, py, pz), (qx, qy, qz) = axis.tolist(), p.tolist(), q.tolist()
    kp, kq = ax * px + ay * py + az * pz, ax * qx + ay * qy + az * qz
    px, py, pz = px - kp * ax, py - kp * ay, pz - kp * az
    qx, qy, qz = qx - kq * ax, qy - kq * ay, qz - kq * az
    cross = ax * (py * qz - pz * qy) + ay * (pz * qx - px * qz) + az * (px * qy - py * qx)
    return math.atan2(cross, px * qx + py * qy + pz * qz)


class ArmPlane(NamedTuple):
    """J1 … J3 of an arm and the point they carry (see the module docstring). ``shoulder``:
    J1's axis (x, y), m; ``s1``: +1 if J1 turns about +z, -1 about -z; ``p2``, ``p3``: J2's and
    J3's axes in the plane (radial, up), m; ``s2``, ``s3``: how a positive J2 / J3 turns the
    plane (+1 anticlockwise from radial towards up); ``wrist``: the carried point at q = 0 in
    the plane (radial, up), m, and ``lateral`` its side offset from J1's axis, m."""

    shoulder: tuple[float, float]
    s1: float
    p2: tuple[float, float]
    s2: float
    p3: tuple[float, float]
    s3: float
    wrist: tuple[float, float]
    lateral: float

    @staticmethod
    def fit(axes: list[Axis], wrist: np.ndarray) -> "ArmPlane | None":
        """From the axes at q = 0 and the carried point (base frame); None unless J1 is
        vertical and J2, J3 lie across the plane (along ±y)."""
        u1, u2, u3 = (snapped(a.direction) for a in axes[:3])
        if abs(u1 @ _Z) != 1.0 or abs(u2 @ _Y) != 1.0 or abs(u3 @ _Y) != 1.0:
            return None
        sx, sy = float(axes[0].point[0]), float(axes[0].point[1])

        def plane(p):
            return float(p[0] - sx), float(p[2])

        # a turn about +y takes radial towards -up: clockwise in the plane
        return ArmPlane((sx, sy), float(u1 @ _Z), plane(axes[1].point), -float(u2 @ _Y),
                        plane(axes[2].point), -float(u3 @ _Y), plane(wrist),
                        float(wrist[1] - sy))

    def place(self, points: np.ndarray, slack: float) -> tuple[np.ndarray, np.ndarray]:
        """J1 … J3 (rad) putting the carried point at each of ``points`` ((N, 3), m, base):
        ``(q (N, 4, 3), valid (N, 4))`` for the four ways (shoulder front / back × elbow one
        way / the other); a way is invalid where the point is out of reach by more than
        ``slack`` (m), and is taken at the edge of reach within it."""
        x = points[:, 0] - self.shoulder[0]
        y = points[:, 1] - self.shoulder[1]
        r = np.hypot(x, y)
        e = self.lateral
        ok_side = r >= abs(e) - slack
        a = np.arcsin(np.clip(e / np.maximum(r, 1e-12), -1.0, 1.0))
        phi = np.arctan2(y, x)
        radial = np.sqrt(np.maximum(r * r - e * e, 0.0))
        psi = np.stack([phi - a, phi - math.pi + a], axis=1)          # (N, 2)
        rho = np.stack([radial, -radial], axis=1)
        (r2, h2), (r3, h3), (rw, hw) = self.p2, self.p3, self.wrist
        L1, L2 = math.hypot(r3 - r2, h3 - h2), math.hypot(rw - r3, hw - h3)
        b1, b2 = math.atan2(h3 - h2, r3 - r2), math.atan2(hw - h3, rw - r3)
        du = rho - r2                                                   # (N, 2)
        dv = np.broadcast_to(points[:, 2:3] - h2, du.shape)
        c = (du * du + dv * dv - L1 * L1 - L2 * L2) / (2.0 * L1 * L2)
        ok_elbow = np.abs(c) <= 1.0 + slack * (L1 + L2) / (L1 * L2)
        g0 = np.arccos(np.clip(c, -1.0, 1.0))
        q = np.empty((len(points), 4, 3))
        valid = np.empty((len(points), 4), bool)
        for i in range(2):                   # shoulder
            for k, g in enumerate((g0[:, i], -g0[:, i])):   # elbow
                col = 2 * i + k
                q[:, col, 0] = self.s1 * psi[:, i]
                q[:, col, 2] = self.s3 * (g - (b2 - b1))
                q[:, col, 1] = self.s2 * (np.arctan2(dv[:, i], du[:, i]) - b1
                                          - np.arctan2(L2 * np.sin(g), L1 + L2 * np.cos(g)))
                valid[:, col] = ok_side & ok_elbow[:, i]
        return q, valid

    def rotate(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The direction ``v`` (3,), fixed to J3's link, after J1 … J3 turn by ``q``
        ((..., 3) rad): ((..., 3))."""
        fold = -(self.s2 * q[..., 1] + self.s3 * q[..., 2])   # about +y (see fit)
        cf, sf = np.cos(fold), np.sin(fold)
        x = cf * v[0] + sf * v[2]
        z = -sf * v[0] + cf * v[2]
        yaw = self.s1 * q[..., 0]
        cy, sy = np.cos(yaw), np.sin(yaw)
        return np.stack([cy * x - sy * v[1], sy * x + cy * v[1], z], axis=-1)

    def rotation(self, q) -> np.ndarray:
        """The rotation (3x3) of J3's link after J1 … J3 turn by ``q`` (rad), from q = 0."""
        return rotvec_to_matrix(_Z * (self.s1 * q[0])) @ rotvec_to_matrix(
            _Y * -(self.s2 * q[1] + self.s3 * q[2]))
