"""The unit edge between the JAKA TCP protocol and the driver.

On the wire (jaka_facts.md §2.2) joints are in **degrees** (speeds deg/s, accelerations deg/s²)
and Cartesian poses are ``[x, y, z, rx, ry, rz]`` in **mm** and **degrees**, the angles being
roll/pitch/yaw with ``R = Rz(rz) · Ry(ry) · Rx(rx)`` (jaka_facts.md §3.2).

Inside the driver (contract.md, "Units and frames") joints are in **radians** and a Cartesian pose
is ``[x, y, z, rx, ry, rz]`` in **mm** and a **rotation vector** (axis × angle, rad).

Every conversion between the two happens here, so a unit mistake can live in one place only.
The rotation maths is private on purpose: the protocol library must not depend on the driver's
kinematics modules (they are written in parallel and may import from here, not the reverse).
"""
from __future__ import annotations

from typing import Iterable, List

import numpy as np

from ..transforms import matrix_to_rotvec, matrix_to_rpy, rotvec_to_matrix, rpy_to_matrix

#: Below this angle (rad) sin(θ)/θ and (1-cos θ)/θ² are evaluated by their Taylor series;
#: the closed forms lose all precision there.
_SMALL_ANGLE = 1e-6
#: When cos θ drops below this the rotation axis is read from the symmetric part of R: near
#: θ = π, sin θ → 0 and the skew part no longer carries the axis.
_NEAR_PI_COS = -0.5
#: cos(pitch) below this means gimbal lock: yaw and roll are no longer separable, yaw is set to 0.
_GIMBAL_COS = 1e-12


# ---- joints --------------------------------------------------------------------------------

def deg_to_rad(values) -> np.ndarray:
    """Degrees (or deg/s, deg/s²) → radians (rad/s, rad/s²), elementwise, as a float array."""
    return np.radians(np.asarray(values, dtype=float))


def rad_to_deg(values) -> np.ndarray:
    """Radians (or rad/s, rad/s²) → degrees (deg/s, deg/s²), elementwise, as a float array."""
    return np.degrees(np.asarray(values, dtype=float))


def joints_to_wire(q_rad: Iterable[float]) -> List[float]:
    """Joint vector in rad → the wire's list of plain floats in degrees."""
    return [float(v) for v in rad_to_deg(q_rad)]


def joints_from_wire(q_deg: Iterable[float]) -> np.ndarray:
    """The wire's joint list in degrees → float array in rad."""
    return deg_to_rad(list(q_deg))


# ---- Cartesian poses -------------------------------------------------------------------------

def pose_to_wire(pose_mm_rotvec: Iterable[float]) -> List[float]:
    """Driver pose ``[x, y, z mm, rotation vector rad]`` → wire pose ``[x, y, z mm, rx, ry, rz
    deg]`` (RPY, ``R = Rz(rz)·Ry(ry)·Rx(rx)``), as plain floats for JSON."""
    p = np.asarray(pose_mm_rotvec, dtype=float).reshape(6)
    rpy = matrix_to_rpy(rotvec_to_matrix(p[3:]))
    return [float(v) for v in p[:3]] + [float(v) for v in np.degrees(rpy)]


def pose_from_wire(wire_pose: Iterable[float]) -> np.ndarray:
    """Wire pose ``[x, y, z mm, rx, ry, rz deg]`` (RPY) → driver pose ``[x, y, z mm, rotation
    vector rad]`` with the rotation angle in [0, π]."""
    p = np.asarray(list(wire_pose), dtype=float).reshape(6)
    rotvec = matrix_to_rotvec(rpy_to_matrix(*np.radians(p[3:])))
    return np.concatenate([p[:3], rotvec])


def rotvec_to_rpy(rotvec) -> np.ndarray:
    """Rotation vector (rad) → roll, pitch, yaw (rad) with ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``;
    pitch in [-π/2, π/2], roll and yaw in (-π, π]."""
    return matrix_to_rpy(rotvec_to_matrix(np.asarray(rotvec, dtype=float)))


def rpy_to_rotvec(rpy) -> np.ndarray:
    """Roll, pitch, yaw (rad, ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``) → rotation vector (rad),
    angle in [0, π]."""
    return matrix_to_rotvec(rpy_to_matrix(*np.asarray(rpy, dtype=float).reshape(3)))


# ---- private rotation maths ------------------------------------------------------------------
