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

import math
from typing import Iterable, List

import numpy as np

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
    rpy = _matrix_to_rpy(_rotvec_to_matrix(p[3:]))
    return [float(v) for v in p[:3]] + [float(v) for v in np.degrees(rpy)]


def pose_from_wire(wire_pose: Iterable[float]) -> np.ndarray:
    """Wire pose ``[x, y, z mm, rx, ry, rz deg]`` (RPY) → driver pose ``[x, y, z mm, rotation
    vector rad]`` with the rotation angle in [0, π]."""
    p = np.asarray(list(wire_pose), dtype=float).reshape(6)
    rotvec = _matrix_to_rotvec(_rpy_to_matrix(np.radians(p[3:])))
    return np.concatenate([p[:3], rotvec])


def rotvec_to_rpy(rotvec) -> np.ndarray:
    """Rotation vector (rad) → roll, pitch, yaw (rad) with ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``;
    pitch in [-π/2, π/2], roll and yaw in (-π, π]."""
    return _matrix_to_rpy(_rotvec_to_matrix(np.asarray(rotvec, dtype=float)))


def rpy_to_rotvec(rpy) -> np.ndarray:
    """Roll, pitch, yaw (rad, ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``) → rotation vector (rad),
    angle in [0, π]."""
    return _matrix_to_rotvec(_rpy_to_matrix(np.asarray(rpy, dtype=float)))


# ---- private rotation maths ------------------------------------------------------------------

def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _rotvec_to_matrix(rotvec: np.ndarray) -> np.ndarray:
    """Rodrigues' formula R = I + a·K + b·K², K = skew(rotvec), a = sin θ/θ, b = (1-cos θ)/θ²."""
    rv = np.asarray(rotvec, dtype=float).reshape(3)
    theta2 = float(rv @ rv)
    theta = math.sqrt(theta2)
    if theta < _SMALL_ANGLE:
        a = 1.0 - theta2 / 6.0
        b = 0.5 - theta2 / 24.0
    else:
        a = math.sin(theta) / theta
        b = (1.0 - math.cos(theta)) / theta2
    k = _skew(rv)
    return np.eye(3) + a * k + b * (k @ k)


def _matrix_to_rotvec(rot: np.ndarray) -> np.ndarray:
    """Inverse of :func:`_rotvec_to_matrix`; the returned angle is in [0, π]."""
    r = np.asarray(rot, dtype=float)
    # sin θ · axis, from the skew-symmetric part; cos θ from the trace.
    s = 0.5 * np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    cos_t = max(-1.0, min(1.0, 0.5 * (np.trace(r) - 1.0)))
    sin_t = float(np.linalg.norm(s))
    theta = math.atan2(sin_t, cos_t)
    if cos_t > _NEAR_PI_COS:
        if theta < _SMALL_ANGLE:
            return s * (1.0 + theta * theta / 6.0)   # θ/sin θ to second order
        return s * (theta / sin_t)
    # Near π: (R + Rᵀ)/2 = cos θ·I + (1 - cos θ)·a·aᵀ; take the best-conditioned column.
    aat = (0.5 * (r + r.T) - cos_t * np.eye(3)) / (1.0 - cos_t)
    i = int(np.argmax(np.diag(aat)))
    axis = aat[:, i] / math.sqrt(max(aat[i, i], 1e-300))
    axis /= np.linalg.norm(axis)
    if axis @ s < 0.0:   # the symmetric part loses the sign; the skew part still has it
        axis = -axis
    return axis * theta


def _rpy_to_matrix(rpy: np.ndarray) -> np.ndarray:
    """R = Rz(yaw) · Ry(pitch) · Rx(roll) for ``rpy = (roll, pitch, yaw)`` in rad."""
    roll, pitch, yaw = (float(v) for v in np.asarray(rpy, dtype=float).reshape(3))
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])


def _matrix_to_rpy(rot: np.ndarray) -> np.ndarray:
    """Inverse of :func:`_rpy_to_matrix`: (roll, pitch, yaw) in rad.

    Yaw comes from the first column; pitch and roll are then read from ``Rz(yaw)ᵀ·R`` instead
    of from R directly. That keeps R exactly reproducible near pitch = ±90°, where yaw itself is
    ill-defined: whatever yaw is picked, roll absorbs the rest of the rotation about z.
    """
    r = np.asarray(rot, dtype=float)
    cos_pitch = math.hypot(r[0, 0], r[1, 0])
    yaw = 0.0 if cos_pitch < _GIMBAL_COS else math.atan2(r[1, 0], r[0, 0])
    cy, sy = math.cos(yaw), math.sin(yaw)
    # Rz(yaw)ᵀ·R = Ry(pitch)·Rx(roll) = [[cp, sp·sr, sp·cr], [0, cr, -sr], [-sp, cp·sr, cp·cr]]
    pitch = math.atan2(-r[2, 0], cy * r[0, 0] + sy * r[1, 0])
    roll = math.atan2(sy * r[0, 2] - cy * r[1, 2], cy * r[1, 1] - sy * r[0, 1])
    return np.array([roll, pitch, yaw])
