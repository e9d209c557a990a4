"""The arm's nominal chain as geometry: joint frames, joint axes at q = 0, the flange at q = 0.

Plain numpy on :attr:`jaka_driver.common.models.RobotModel.chain` (the URDF's joints as written), so
the same geometry can be read without Pinocchio and compared with any other description of
the arm — DH parameters, a controller's own — by the lines its joints turn about at q = 0 and
the flange pose there, which do not depend on how a file chooses its link frames. The IK
solvers (:mod:`.closed_form`, :mod:`.arm_plane`) measure their lengths from it.

Units: m, rad. Frames: every pose and axis is in the base frame (``base_link``, the mounting
face); poses are 4x4 homogeneous matrices.
"""
from __future__ import annotations

from typing import NamedTuple, Sequence

import numpy as np

from ..common.models import Placement
from ..common.transforms import rotvec_to_matrix, rpy_to_matrix


class Axis(NamedTuple):
    """A joint's line: a ``point`` on it (m; the joint frame's origin) and its unit
    ``direction`` (the sense the joint turns positively about), base frame."""

    point: np.ndarray
    direction: np.ndarray


def _origin(p: Placement) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = rpy_to_matrix(*p.rpy)
    T[:3, 3] = p.xyz
    return T


def joint_frames(chain: Sequence[Placement], q) -> tuple[list[np.ndarray], np.ndarray]:
    """(pose of each revolute joint's frame after its rotation, flange pose), 4x4 in the base
    frame, for joint positions ``q`` (rad, one per revolute joint in chain order)."""
    q = iter(np.asarray(q, float).tolist())
    T = np.eye(4)
    frames = []
    for p in chain:
        T = T @ _origin(p)
        if p.kind == "revolute":
            J = np.eye(4)
            axis = np.asarray(p.axis, float)
            J[:3, :3] = rotvec_to_matrix(axis / np.linalg.norm(axis) * next(q))
            T = T @ J
            frames.append(T)
    return frames, T


def axes_at_zero(chain: Sequence[Placement]) -> tuple[list[Axis], np.ndarray]:
    """(the joints' axes at q = 0, the flange pose at q = 0), base frame."""
    n = sum(p.kind == "revolute" for p in chain)
    frames, flange = joint_frames(chain, np.zeros(n))
    axes = []
    for F, p in zip(frames, (p for p in chain if p.kind == "revolute")):
        d = F[:3, :3] @ np.asarray(p.axis, float)
        axes.append(Axis(F[:3, 3].copy(), d / np.linalg.norm(d)))
    return axes, flange


def closest_points(a: Axis, b: Axis) -> tuple[np.ndarray, np.ndarray]:
    """The points of lines ``a`` and ``b`` nearest each other (for parallel lines: ``a``'s
    point and its foot on ``b``)."""
    w = a.point - b.point
    u, v = a.direction, b.direction
    uv = float(u @ v)
    den = 1.0 - uv * uv
    if den < 1e-12:
        return a.point, b.point + float(w @ v) * v
    s = (uv * float(w @ v) - float(w @ u)) / den
    t = (float(w @ v) - uv * float(w @ u)) / den
    return a.point + s * u, b.point + t * v


def snapped(direction: np.ndarray, tolerance: float = 1e-3) -> np.ndarray:
    """``direction`` turned onto the nearest base axis (±x, ±y, ±z) when within ``tolerance``
    rad of it — JAKA writes π/2 as 1.5708 and has 1e-4 rad tilts in places — else as it is."""
    k = int(np.argmax(np.abs(direction)))
    if abs(direction[k]) >= np.cos(tolerance):
        out = np.zeros(3)
        out[k] = np.sign(direction[k])
        return out
    return direction


def z_axis_placements(chain: Sequence[Placement]) -> tuple[list[tuple[np.ndarray, np.ndarray]],
                                                            np.ndarray]:
    """The revolute joints re-expressed to turn about their own z: ``(placements, fix)`` with
    each placement (rotation 3x3, translation m) of a joint's frame in the previous joint's
    frame (the first in the base frame), and ``fix`` (4x4) the pose of the last joint's frame
    as the file has it in the re-expressed last frame. The chain's motion is unchanged: a joint
    about axis a is A·Rz(q)·Aᵀ with A turning z onto a, and each A moves into the placements
    around it."""
    out = []
    pending = np.eye(4)     # fixed transforms since the last revolute joint
    A_prev = np.eye(3)
    for p in chain:
        pending = pending @ _origin(p)
        if p.kind != "revolute":
            continue
        A = _z_onto(np.asarray(p.axis, float))
        out.append((A_prev.T @ pending[:3, :3] @ A, A_prev.T @ pending[:3, 3]))
        A_prev, pending = A, np.eye(4)
    fix = np.eye(4)
    fix[:3, :3] = A_prev.T
    return out, fix


def _z_onto(axis: np.ndarray) -> np.ndarray:
    """A rotation taking z onto the unit vector along ``axis`` (identity for z itself)."""
    a = axis / np.linalg.norm(axis)
    z = np.array([0.0, 0.0, 1.0])
    c = float(z @ a)
    if c > 1.0 - 1e-15:
        return np.eye(3)
    if c < -1.0 + 1e-15:
        return np.diag([1.0, -1.0, -1.0])
    v = np.cross(z, a)
    return rotvec_to_matrix(v / np.linalg.norm(v) * np.arccos(c))
