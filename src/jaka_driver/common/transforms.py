"""Rotations and poses in numpy: rotation vectors, JAKA RPY, ROS quaternions, 4x4 matrices.

Conventions (the JAKA controller's and ROS's):

* A rotation matrix ``R`` maps vectors of the rotated frame into the reference frame; a 4x4
  homogeneous ``T = [[R, p], [0, 1]]`` is the pose of a frame in a reference frame.
* RPY ``(rx, ry, rz)`` in rad means ``R = Rz(rz) · Ry(ry) · Rx(rx)`` (fixed-axis X, then Y, then Z),
  which is what the JAKA API calls RPY and what ``tf`` calls RPY.
* A rotation vector is ``angle · axis`` (rad), angle in [0, π].
* Quaternions are ``(x, y, z, w)``, the ROS order, returned with ``w >= 0``.
* A 6-vector pose is ``(x, y, z, r1, r2, r3)``: translation then rotation vector or RPY.
  ``length_scale`` is the size of one translation unit in metres (1e-3: the pose is in mm,
  the matrix always in m).

Rotation functions accept a single value or a stack (leading dimensions); the output has the same
leading dimensions.
"""
from __future__ import annotations

import math

import numpy as np

_SMALL = 1e-6  # below this angle (rad) the series expansions are exact to double precision


def _skew(v: np.ndarray) -> np.ndarray:
    """(..., 3) → (..., 3, 3) with skew(v) @ u == cross(v, u)."""
    z = np.zeros_like(v[..., 0])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([z, -w, y], -1), np.stack([w, z, -x], -1),
                     np.stack([-y, x, z], -1)], -2)


def rotvec_to_matrix(rotvec) -> np.ndarray:
    """Rotation vector(s) (rad, ``(..., 3)``) → rotation matrix (``(..., 3, 3)``), Rodrigues."""
    v = np.asarray(rotvec, dtype=float)
    if v.shape == (3,):
        return np.array(_one_rotation(*v.tolist()))
    theta2 = np.einsum("...i,...i->...", v, v)
    theta = np.sqrt(theta2)
    small = theta < _SMALL
    safe = np.where(small, 1.0, theta)
    # sin(t)/t and (1-cos t)/t² with their Taylor series near 0, where the quotients lose digits.
    a = np.where(small, 1.0 - theta2 / 6.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - theta2 / 24.0, (1.0 - np.cos(safe)) / (safe * safe))
    K = _skew(v)
    return np.eye(3) + a[..., None, None] * K + b[..., None, None] * (K @ K)


def _one_rotation(x: float, y: float, z: float) -> tuple:
    """:func:`rotvec_to_matrix` of one vector in plain floats (the same series and Rodrigues'
    formula), ~10× faster than the stacked numpy path for a velocity jog's step every cycle.
    K² of the skew matrix K of v is v vᵀ − θ² I."""
    theta2 = x * x + y * y + z * z
    if theta2 < _SMALL * _SMALL:
        a, b = 1.0 - theta2 / 6.0, 0.5 - theta2 / 24.0
    else:
        theta = math.sqrt(theta2)
        a, b = math.sin(theta) / theta, (1.0 - math.cos(theta)) / (theta * theta)
    return ((1.0 + b * (x * x - theta2), b * x * y - a * z, b * x * z + a * y),
            (b * x * y + a * z, 1.0 + b * (y * y - theta2), b * y * z - a * x),
            (b * x * z - a * y, b * y * z + a * x, 1.0 + b * (z * z - theta2)))


def matrix_to_quat(R) -> np.ndarray:
    """Rotation matrix(es) → unit quaternion(s) ``(x, y, z, w)`` with ``w >= 0``.

    Uses the largest of the four diagonal combinations (Shepperd), so it is accurate at every
    angle, including 0 and π.
    """
    R = np.asarray(R, dtype=float)
    if R.shape == (3, 3):
        return np.array(_one_quat(R.tolist()))
    m00, m11, m22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    # 4·q_i² for i = w, x, y, z; the largest one gives a well-conditioned division.
    cand = np.stack([1 + m00 + m11 + m22, 1 + m00 - m11 - m22,
                     1 - m00 + m11 - m22, 1 - m00 - m11 + m22], -1)
    k = np.argmax(cand, axis=-1)
    s = np.sqrt(np.maximum(np.take_along_axis(cand, k[..., None], -1)[..., 0], 1e-300))
    d21, d02, d10 = R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]
    s21, s02, s10 = R[..., 2, 1] + R[..., 1, 2], R[..., 0, 2] + R[..., 2, 0], R[..., 1, 0] + R[..., 0, 1]
    q = np.stack([
        np.stack([d21, d02, d10, s * s], -1),   # k = 0: w largest
        np.stack([s * s, s10, s02, d21], -1),   # k = 1: x largest
        np.stack([s10, s * s, s21, d02], -1),   # k = 2: y largest
        np.stack([s02, s21, s * s, d10], -1),   # k = 3: z largest
    ], -2)
    q = np.take_along_axis(q, k[..., None, None], -2)[..., 0, :] / (2.0 * s[..., None])
    q = np.where(q[..., 3:4] < 0, -q, q)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def _one_quat(r: list) -> tuple[float, float, float, float]:
    """:func:`matrix_to_quat` of one matrix (nested lists) in plain floats: the same
    Shepperd branches, ~10× faster than the stacked numpy path for the TCP pose that every
    state message carries."""
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = r
    cand = (1 + m00 + m11 + m22, 1 + m00 - m11 - m22, 1 - m00 + m11 - m22, 1 - m00 - m11 + m22)
    k = max(range(4), key=cand.__getitem__)
    s = math.sqrt(max(cand[k], 1e-300))
    d21, d02, d10 = m21 - m12, m02 - m20, m10 - m01
    s21, s02, s10 = m21 + m12, m02 + m20, m10 + m01
    q = ((d21, d02, d10, s * s), (s * s, s10, s02, d21), (s10, s * s, s21, d02),
         (s02, s21, s * s, d10))[k]
    sign = -1.0 if q[3] < 0 else 1.0
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) * sign
    return q[0] / n, q[1] / n, q[2] / n, q[3] / n


def quat_to_matrix(quat) -> np.ndarray:
    """Quaternion(s) ``(x, y, z, w)`` (normalised here) → rotation matrix(es)."""
    q = np.asarray(quat, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def matrix_to_rotvec(R) -> np.ndarray:
    """Rotation matrix(es) → rotation vector(s) (rad), angle in [0, π].

    Goes through the quaternion, so it stays accurate near 0 and near π (where ``arccos`` of the
    trace loses half the digits). At exactly π the sign of the axis is arbitrary.
    """
    R = np.asarray(R, dtype=float)
    if R.shape == (3, 3):
        x, y, z, w = _one_quat(R.tolist())
        n = math.sqrt(x * x + y * y + z * z)
        scale = 2.0 / (w if w else 1.0) if n < _SMALL else 2.0 * math.atan2(n, w) / n
        return np.array((x * scale, y * scale, z * scale))
    q = matrix_to_quat(R)
    v, w = q[..., :3], q[..., 3]
    n = np.linalg.norm(v, axis=-1)
    # angle/ sin(angle/2) = 2·atan2(n, w)/n → 2/w for tiny n (w ≈ 1 there).
    scale = np.where(n < _SMALL, 2.0 / np.where(w == 0, 1.0, w),
                     2.0 * np.arctan2(n, w) / np.where(n == 0, 1.0, n))
    return v * scale[..., None]


def _one_rpy(rx: float, ry: float, rz: float) -> tuple:
    """:func:`rpy_to_matrix` of one set of angles in plain floats (the same products)."""
    cx, sx, cy, sy = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry)
    cz, sz = math.cos(rz), math.sin(rz)
    return ((cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx),
            (sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx),
            (-sy, cy * sx, cy * cx))


def rpy_to_matrix(rx, ry, rz) -> np.ndarray:
    """JAKA/ROS RPY angles (rad) → ``Rz(rz) · Ry(ry) · Rx(rx)``."""
    rx, ry, rz = (np.asarray(a, dtype=float) for a in (rx, ry, rz))
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    return np.stack([
        np.stack([cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx], -1),
        np.stack([sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx], -1),
        np.stack([-sy, cy * sx, cy * cx], -1),
    ], -2)


def matrix_to_rpy(R) -> np.ndarray:
    """Rotation matrix(es) → ``(rx, ry, rz)`` rad with ry in [-π/2, π/2], rx, rz in (-π, π].

    At gimbal lock (ry = ±π/2) only rz ∓ rx is defined; rx is then set to 0.
    """
    R = np.asarray(R, dtype=float)
    if R.shape == (3, 3):
        return np.array(_one_matrix_rpy(R.tolist()))
    cy = np.hypot(R[..., 0, 0], R[..., 1, 0])
    ry = np.arctan2(-R[..., 2, 0], cy)
    lock = cy < 1e-9
    rz = np.where(lock, np.arctan2(-R[..., 0, 1], R[..., 1, 1]), np.arctan2(R[..., 1, 0], R[..., 0, 0]))
    # rx from what is left once rz and ry are taken out (Ry(ry)ᵀ·Rz(rz)ᵀ·R = Rx(rx)), not from
    # R[2, 1] and R[2, 2]: near gimbal lock those are both ~cos(ry), and their ratio then loses
    # digits (an error of eps / cos(ry) in rx that rz does not make up). This way the three
    # angles give R back to a few eps whatever rz's own error.
    sz, cz = np.sin(rz), np.cos(rz)
    sy, cyy = np.sin(ry), np.cos(ry)
    m11 = -sz * R[..., 0, 1] + cz * R[..., 1, 1]
    m21 = sy * (cz * R[..., 0, 1] + sz * R[..., 1, 1]) + cyy * R[..., 2, 1]
    rx = np.where(lock, 0.0, np.arctan2(m21, m11))
    return np.stack([rx, ry, rz], -1)


def _one_matrix_rpy(r: list) -> tuple[float, float, float]:
    """:func:`matrix_to_rpy` of one matrix (nested lists) in plain floats: the same steps,
    ~10× faster than the stacked numpy path for the two poses every emulator packet carries."""
    (r00, r01, _), (r10, r11, _), (r20, r21, _) = r
    cy = math.hypot(r00, r10)
    ry = math.atan2(-r20, cy)
    if cy < 1e-9:
        return 0.0, ry, math.atan2(-r01, r11)
    rz = math.atan2(r10, r00)
    sz, cz, sy, cyy = math.sin(rz), math.cos(rz), math.sin(ry), math.cos(ry)
    m11 = -sz * r01 + cz * r11
    m21 = sy * (cz * r01 + sz * r11) + cyy * r21
    return math.atan2(m21, m11), ry, rz


def _rotation_from(r3: np.ndarray, rotation: str) -> np.ndarray:
    if rotation == "rotvec":
        return rotvec_to_matrix(r3)
    if rotation == "rpy":
        return rpy_to_matrix(r3[..., 0], r3[..., 1], r3[..., 2])
    raise ValueError(f"rotation must be 'rotvec' or 'rpy', got {rotation!r}")


def pose_to_matrix(pose6, *, rotation: str = "rotvec", length_scale: float = 1.0) -> np.ndarray:
    """6-vector pose ``(x, y, z, r1, r2, r3)`` → 4x4 homogeneous matrix in metres.

    ``rotation``: ``"rotvec"`` (rad) or ``"rpy"`` (rad, JAKA order). ``length_scale``: metres per
    translation unit of ``pose6`` (1e-3 for mm).
    """
    p = np.asarray(pose6, dtype=float)
    if p.shape[-1] != 6:
        raise ValueError(f"a pose has 6 values, got shape {p.shape}")
    if p.shape == (6,) and rotation == "rpy":
        # one pose in plain floats (a controller's status packet, 125 times a second)
        x, y, z, rx, ry, rz = p.tolist()
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = _one_rpy(rx, ry, rz)
        return np.array(((r00, r01, r02, x * length_scale), (r10, r11, r12, y * length_scale),
                         (r20, r21, r22, z * length_scale), (0.0, 0.0, 0.0, 1.0)))
    T = np.zeros(p.shape[:-1] + (4, 4))
    T[..., :3, :3] = _rotation_from(p[..., 3:], rotation)
    T[..., :3, 3] = p[..., :3] * length_scale
    T[..., 3, 3] = 1.0
    return T


def matrix_to_pose(T, *, rotation: str = "rotvec", length_scale: float = 1.0) -> np.ndarray:
    """4x4 homogeneous matrix (m) → 6-vector pose; inverse of :func:`pose_to_matrix`."""
    T = np.asarray(T, dtype=float)
    if rotation == "rotvec":
        r = matrix_to_rotvec(T[..., :3, :3])
    elif rotation == "rpy":
        r = matrix_to_rpy(T[..., :3, :3])
    else:
        raise ValueError(f"rotation must be 'rotvec' or 'rpy', got {rotation!r}")
    return np.concatenate([T[..., :3, 3] / length_scale, r], -1)


def pose_mm_to_matrix(pose_mm_rotvec) -> np.ndarray:
    """The driver's pose at its edges — mm + rotation vector (rad), as the services speak it —
    as a 4x4 in metres. (The protocol library speaks mm + RPY rad, the SDK's units.)"""
    return pose_to_matrix(pose_mm_rotvec, rotation="rotvec", length_scale=1e-3)


def matrix_to_pose_mm(T) -> np.ndarray:
    """A 4x4 in metres as mm + rotation vector (rad); the inverse of :func:`pose_mm_to_matrix`."""
    return matrix_to_pose(T, rotation="rotvec", length_scale=1e-3)


def pose_mm_rpy_to_matrix(pose_mm_rpy) -> np.ndarray:
    """The SDK's pose — mm + RPY (rad), as the controller protocol speaks it — as a 4x4 in
    metres."""
    return pose_to_matrix(pose_mm_rpy, rotation="rpy", length_scale=1e-3)


def matrix_to_pose_mm_rpy(T) -> np.ndarray:
    """A 4x4 in metres as mm + RPY (rad); the inverse of :func:`pose_mm_rpy_to_matrix`."""
    return matrix_to_pose(T, rotation="rpy", length_scale=1e-3)


def rotation_angle_between(R0, R1) -> np.ndarray | float:
    """Angle (rad, [0, π]) of the rotation taking ``R0`` to ``R1``, accurate at 0 and π."""
    D = np.swapaxes(np.asarray(R0, dtype=float), -1, -2) @ np.asarray(R1, dtype=float)
    # atan2(sin, cos) stays accurate where arccos((tr-1)/2) alone would not.
    s = 0.5 * np.linalg.norm(np.stack([D[..., 2, 1] - D[..., 1, 2], D[..., 0, 2] - D[..., 2, 0],
                                       D[..., 1, 0] - D[..., 0, 1]], -1), axis=-1)
    c = 0.5 * (D[..., 0, 0] + D[..., 1, 1] + D[..., 2, 2] - 1.0)
    angle = np.arctan2(s, c)
    return float(angle) if angle.ndim == 0 else angle


def slerp(R0, R1, s) -> np.ndarray:
    """Rotation a fraction ``s`` (0 → R0, 1 → R1) of the shortest way from ``R0`` to ``R1``.

    ``s`` may be a scalar or an array; an array gives a stack ``s.shape + (3, 3)``. The rotation
    axis is fixed in the R0 frame, the angle grows linearly with ``s``.
    """
    R0 = np.asarray(R0, dtype=float)
    rv = matrix_to_rotvec(R0.T @ np.asarray(R1, dtype=float))
    s = np.asarray(s, dtype=float)
    return R0 @ rotvec_to_matrix(s[..., None] * rv)
