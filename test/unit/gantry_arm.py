"""A fake 6-DoF "Cartesian gantry" for the path planners' tests: joints 1-3 are the TCP position
(m), joints 4-6 the rotation vector of its orientation (rad), so FK and IK are closed-form and
exact (rotations well below π: the rotation vector jumps at π)."""
import numpy as np


def rot(rotvec):
    rotvec = np.asarray(rotvec, float)
    angle = np.linalg.norm(rotvec)
    if angle < 1e-15:
        return np.eye(3)
    k = rotvec / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def log(R):
    """Rotation vector of R (angles well below π in these tests)."""
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return w * angle / (2 * np.sin(angle))


def pose(p, rotvec=(0, 0, 0)):
    T = np.eye(4)
    T[:3, :3] = rot(rotvec)
    T[:3, 3] = p
    return T


def gantry_fk(q):
    return pose(q[:3], q[3:])


def gantry_ik(T, seed):
    return np.concatenate([T[:3, 3], log(T[:3, :3])])


def gantry_ik_unwrapped(T, seed):
    """As :func:`gantry_ik`, the rotation vector continued past π: of its equivalents
    (angle ± 2π about the same axis) the one nearest ``seed``'s (rotations of any size)."""
    q = gantry_ik(T, seed)
    r = q[3:]
    angle = np.linalg.norm(r)
    if seed is None or angle < 1e-12:
        return q
    axis = r / angle
    candidates = [r + k * 2 * np.pi * axis for k in (-2, -1, 0, 1, 2)]
    q[3:] = min(candidates, key=lambda c: np.linalg.norm(c - seed[3:]))
    return q
