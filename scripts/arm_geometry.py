"""The shapes and mass properties of a generated arm: simple cylinders laid along JAKA's chain.

JAKA's meshes are not used (their masses are CAD defaults, and the driver needs no meshes): each
arm is drawn from its own joint axes at q = 0 — a drum on every joint axis, a tube from each
joint to the next, a base column and a flange disc — so one rule draws all three kinematic
structures. Shapes are laid out in the base frame at q = 0 and then expressed in their link's
frame, whatever orientation JAKA's file gives that frame (the S7's, the C12's wrist).

Units: m, kg, kg·m². Frames: ``base_link`` (the mounting face) and the link frames of the URDF.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from arm_catalogue import Arm
from jaka_driver.common.transforms import rotvec_to_matrix, rpy_to_matrix

FLANGE_T = 0.012        # m, flange disc thickness
MIN_TUBE = 0.005        # m, shorter connections are not drawn


def link_frames(arm: Arm, q=None) -> list[np.ndarray]:
    """Poses (4x4, base frame) of link_0 … link_6 at joint positions ``q`` (rad; default 0)."""
    q = np.zeros(6) if q is None else np.asarray(q, float)
    T = np.eye(4)
    T[:3, 3] = arm.mount
    out = [T]
    for row, qi in zip(arm.joints, q):
        J = np.eye(4)
        axis = np.asarray(row.axis) / np.linalg.norm(row.axis)
        J[:3, :3] = rpy_to_matrix(*row.rpy) @ rotvec_to_matrix(axis * qi)
        J[:3, 3] = row.xyz
        T = T @ J
        out.append(T)
    return out


@dataclass(frozen=True)
class Cylinder:
    """A solid cylinder in a link frame: centre (m), unit axis direction, radius, length (m),
    ``material`` "arm" (light covers) or "joint" (dark joint modules)."""

    centre: tuple[float, float, float]
    direction: tuple[float, float, float]
    radius: float
    length: float
    material: str

    @property
    def volume(self) -> float:
        return np.pi * self.radius ** 2 * self.length

    @property
    def rpy(self) -> tuple[float, float, float]:
        """URDF rpy turning the cylinder's own z (its axis) onto its direction: a pitch from z,
        then a yaw about z (a cylinder needs no roll about its own axis)."""
        dx, dy, dz = self.direction
        across = float(np.hypot(dx, dy))
        return 0.0, float(np.arctan2(across, dz)), float(np.arctan2(dy, dx)) if across else 0.0

    @property
    def rotation(self) -> np.ndarray:
        return rpy_to_matrix(*self.rpy)

    def inertia_about_centre(self, mass: float) -> np.ndarray:
        """Inertia tensor (kg·m²) about the centre, in link-frame axes."""
        r, h = self.radius, self.length
        own = np.diag([mass * (3 * r * r + h * h) / 12.0] * 2 + [0.5 * mass * r * r])
        R = self.rotation
        return R @ own @ R.T


def _segment(a: np.ndarray, b: np.ndarray, radius: float, material: str) -> Cylinder | None:
    """Cylinder from point ``a`` to point ``b`` (base frame), or None when shorter than
    :data:`MIN_TUBE`."""
    d = b - a
    length = float(np.linalg.norm(d))
    if length < MIN_TUBE:
        return None
    return Cylinder(tuple(0.5 * (a + b)), tuple(d / length), radius, length, material)


def radii(payload_kg: float) -> tuple[float, float]:
    """(upper-arm tube radius, wrist drum radius) in m by payload class: the size of the
    modules grows with what the arm carries."""
    for limit, r_arm, r_wrist in ((1, 0.035, 0.030), (3, 0.045, 0.040), (7, 0.060, 0.045),
                                  (18, 0.075, 0.050), (30, 0.090, 0.060)):
        if payload_kg <= limit:
            return r_arm, r_wrist
    raise ValueError(f"no size class for a {payload_kg} kg payload")


def link_geometry(arm: Arm) -> list[list[Cylinder]]:
    """Cylinders of link_0 … link_6, each in its own link frame.

    At q = 0, with o_i the origin and u_i the axis of joint i in the base frame (o_7 the
    flange): link i (1…6) carries a drum on u_i spanning o_i and the foot of o_{i+1} on that
    axis, and a tube from that foot to o_{i+1}; link_0 a column from the mounting face up the
    J1 axis; link_6 the flange disc, its outer face in the flange frame's z = 0.
    """
    frames = link_frames(arm)
    r_arm, r_wrist = radii(arm.payload_kg)
    r_joint = 1.1 * r_arm                 # shoulder/elbow modules a little wider than the tubes
    drum = [r_joint] * 3 + [r_wrist] * 3
    tube = [r_arm, 0.85 * r_arm, 0.9 * r_wrist, r_wrist]     # links 2…5
    o = [T[:3, 3] for T in frames[1:]] + [frames[6][:3, 3]]
    u = [T[:3, :3] @ np.asarray(row.axis) / np.linalg.norm(row.axis)
         for T, row in zip(frames[1:], arm.joints)]
    world: list[list[Cylinder]] = [[] for _ in range(7)]
    # link_0: the base column, from the mounting face to just below the J1 module.
    foot = o[0] - (o[0][2] / u[0][2]) * u[0]
    top = o[0] - drum[0] * u[0]
    if np.linalg.norm(top - foot) < 0.03:
        top = foot + 0.03 * u[0]
    world[0].append(_segment(foot, top, 1.15 * r_arm, "arm"))
    for i in range(5):
        s = float((o[i + 1] - o[i]) @ u[i])        # the next joint's foot on this axis
        lo, hi = min(0.0, s) - drum[i], max(0.0, s) + drum[i]
        world[i + 1].append(_segment(o[i] + lo * u[i], o[i] + hi * u[i], drum[i], "joint"))
        foot = o[i] + s * u[i]
        gap = o[i + 1] - foot
        reach = float(np.linalg.norm(gap))
        if reach > MIN_TUBE and i >= 1:
            d = gap / reach
            end = FLANGE_T if i == 4 else drum[i + 1]
            piece = _segment(foot + drum[i] * d, o[i + 1] - end * d, tube[i - 1], "arm")
            if piece is not None:
                world[i + 1].append(piece)
    world[6].append(_segment(o[6] - FLANGE_T * u[5], o[6], 0.7 * r_wrist, "joint"))
    out = []
    for T, cyls in zip(frames, world):
        R, p = T[:3, :3], T[:3, 3]
        out.append([Cylinder(tuple(R.T @ (np.asarray(c.centre) - p)),
                             _clean(R.T @ np.asarray(c.direction)), c.radius, c.length,
                             c.material) for c in cyls if c is not None])
    return out


def _clean(direction: np.ndarray) -> tuple[float, float, float]:
    """A unit direction without the rounding noise of the frame products (components below
    1e-9 are zero), so an axis-aligned shape is written as one."""
    d = np.where(np.abs(direction) < 1e-9, 0.0, direction)
    return tuple(float(x) for x in d / np.linalg.norm(d))


def link_inertial(cyls: list[Cylinder], mass: float) -> tuple[np.ndarray, np.ndarray]:
    """COM (m) and inertia about it (kg·m², link axes) of solid cylinders of one density."""
    vols = np.array([c.volume for c in cyls])
    masses = mass * vols / vols.sum()
    centres = np.array([c.centre for c in cyls])
    com = masses @ centres / mass
    inertia = np.zeros((3, 3))
    for c, m, p in zip(cyls, masses, centres):
        d = p - com
        inertia += c.inertia_about_centre(m) + m * (d @ d * np.eye(3) - np.outer(d, d))
    return com, inertia
