"""A Cartesian pose as linear_move and get_ik read it and get_fk answers it: position mm,
orientation rad as the conventions say — a rotation vector (the interface document) or RPY
``R = Rz(rz)·Ry(ry)·Rx(rx)`` (JAKA's driver code since 2025-04, which hands the request's
numbers to its SDK's linear_move / kine_inverse and its kine_forward's answer back as they are).

In ``document`` mode a pose whose three angles mean very different orientations read the two
ways is still read as a rotation vector, but the answer says so (:func:`reading_note`): a
program written for JAKA's driver code sends RPY, and a reachable target read the other way
would move the arm somewhere its author did not mean.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np

from ..common.transforms import matrix_to_pose, pose_to_matrix, rotation_angle_between
from .choice import RPY, Conventions

#: rad: the two readings of a pose's angles further apart than this are worth a note
#: (small rotations read almost alike either way: they differ only in second order)
READINGS_APART = math.radians(10.0)

_ROTATION = {RPY: "rpy"}   # transforms' names; the rest is "rotvec"


def pose_to_matrix_mm(conventions: Conventions, pose_mm: Sequence[float]) -> np.ndarray:
    """mm + orientation (rad, as ``conventions`` read it) → 4x4 in metres."""
    return pose_to_matrix(pose_mm, rotation=_ROTATION.get(conventions.cartesian_rotation,
                                                          "rotvec"), length_scale=1e-3)


def matrix_to_pose_mm(conventions: Conventions, T: np.ndarray) -> list[float]:
    """4x4 in metres → mm + orientation (rad, as ``conventions`` write it)."""
    pose = matrix_to_pose(T, rotation=_ROTATION.get(conventions.cartesian_rotation, "rotvec"),
                          length_scale=1e-3)
    return [float(x) for x in pose]


def readings_apart(pose_mm: Sequence[float]) -> float:
    """rad between the orientation of ``pose_mm``'s angles read as a rotation vector and read
    as RPY."""
    angles = [0.0, 0.0, 0.0, *[float(a) for a in pose_mm[3:6]]]
    as_rotvec = pose_to_matrix(angles, rotation="rotvec")[:3, :3]
    as_rpy = pose_to_matrix(angles, rotation="rpy")[:3, :3]
    return float(rotation_angle_between(as_rotvec, as_rpy))


def reading_note(conventions: Conventions, field: str, pose_mm: Sequence[float]
                 ) -> Optional[str]:
    """For ``document`` conventions, a note when ``field``'s angles mean orientations more than
    :data:`READINGS_APART` apart as a rotation vector and as RPY: which reading was used and
    how to get the other. None otherwise (and always for ``jaka_code``, which reads RPY)."""
    if conventions.cartesian_rotation == RPY or len(pose_mm) < 6:
        return None
    apart = readings_apart(pose_mm)
    if not apart > READINGS_APART:
        return None
    return (f"{field} orientation read as a rotation vector (the interface document's "
            f"convention); read as RPY, as JAKA's driver code reads it, it would be "
            f"{math.degrees(apart):.0f}° away: start the driver with conventions:=jaka_code "
            f"for programs written for JAKA's driver")
