"""Rotation/pose conversions round-trip, including the hard angles near 0 and near π."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings, strategies as st

from jaka_driver.common.transforms import (matrix_to_pose, matrix_to_quat, matrix_to_rotvec,
                                    matrix_to_rpy, pose_to_matrix, quat_to_matrix,
                                    rotation_angle_between, rotvec_to_matrix, rpy_to_matrix,
                                    slerp)

unit = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(lambda v: np.linalg.norm(v) > 0.1)
# Angles concentrated where formulas break: exactly/almost 0 and π, plus the general case.
angle = st.one_of(
    st.just(0.0),
    st.floats(1e-15, 1e-5),
    st.floats(np.pi - 1e-5, np.pi),
    st.just(np.pi),
    st.floats(0.0, np.pi),
)


def _rotvec(axis, theta):
    return axis / np.linalg.norm(axis) * theta


def _is_rotation(R):
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert abs(np.linalg.det(R) - 1.0) < 1e-12


@settings(max_examples=300, deadline=None)
@given(unit, angle)
def test_rotvec_matrix_round_trip(axis, theta):
    rv = _rotvec(axis, theta)
    R = rotvec_to_matrix(rv)
    _is_rotation(R)
    np.testing.assert_allclose(R, pin.exp3(rv), atol=1e-12)
    back = matrix_to_rotvec(R)
    np.testing.assert_allclose(rotvec_to_matrix(back), R, atol=1e-12)
    assert np.linalg.norm(back) <= np.pi + 1e-12
    if theta < np.pi - 1e-6:  # below π the rotation vector is unique
        np.testing.assert_allclose(back, rv, atol=1e-12, rtol=1e-9)


@settings(max_examples=300, deadline=None)
@given(unit, angle)
def test_quaternion_round_trip_in_ros_order(axis, theta):
    R = rotvec_to_matrix(_rotvec(axis, theta))
    q = matrix_to_quat(R)
    assert q[3] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-12
    np.testing.assert_allclose(quat_to_matrix(q), R, atol=1e-12)
    # Same (x, y, z, w) as Pinocchio/Eigen, up to the sign of the quaternion.
    ref = pin.Quaternion(R).coeffs()
    assert min(np.abs(q - ref).max(), np.abs(q + ref).max()) < 1e-12


@settings(max_examples=300, deadline=None)
@given(st.floats(-np.pi, np.pi), st.floats(-np.pi / 2, np.pi / 2), st.floats(-np.pi, np.pi))
def test_rpy_is_rz_ry_rx_and_round_trips(rx, ry, rz):
    R = rpy_to_matrix(rx, ry, rz)
    np.testing.assert_allclose(R, pin.rpy.rpyToMatrix(rx, ry, rz), atol=1e-12)
    back = matrix_to_rpy(R)
    np.testing.assert_allclose(rpy_to_matrix(*back), R, atol=1e-9)
    if abs(abs(ry) - np.pi / 2) > 1e-3 and abs(abs(rx) - np.pi) > 1e-9 and abs(abs(rz) - np.pi) > 1e-9:
        np.testing.assert_allclose(back, [rx, ry, rz], atol=1e-9)


def test_rpy_gimbal_lock_keeps_the_rotation():
    for ry in (np.pi / 2, -np.pi / 2):
        R = rpy_to_matrix(0.3, ry, -0.2)
        rx2, ry2, rz2 = matrix_to_rpy(R)
        assert rx2 == 0.0 and abs(ry2 - ry) < 1e-7
        np.testing.assert_allclose(rpy_to_matrix(rx2, ry2, rz2), R, atol=1e-9)


def test_rpy_just_off_gimbal_lock_keeps_the_rotation():
    """Pitch a few 1e-9 rad off ±90°, where R[2, 1] and R[2, 2] are both ~1e-9: the angles still
    give the rotation back to ~1e-9 (reading rx from those two alone was off by up to 2e-7, as
    the protocol's round trip once found with hypothesis)."""
    rng = np.random.default_rng(7)
    for rotvec in ([2.16435571e-09, np.pi / 2, -3.92151079e-09],
                   *([e * rng.uniform(-1, 1), s * np.pi / 2 + e * rng.uniform(-1, 1),
                      e * rng.uniform(-1, 1)]
                     for e in np.logspace(-9, -6, 400) for s in (1, -1))):
        R = rotvec_to_matrix(np.asarray(rotvec))
        np.testing.assert_allclose(rpy_to_matrix(*matrix_to_rpy(R)), R, atol=3e-9)


@settings(max_examples=200, deadline=None)
@given(st.tuples(*[st.floats(-2000, 2000)] * 3), unit, angle, st.sampled_from(["rotvec", "rpy"]))
def test_pose_round_trip_in_mm(xyz_mm, axis, theta, rotation):
    T = np.eye(4)
    T[:3, :3] = rotvec_to_matrix(_rotvec(axis, theta))
    T[:3, 3] = np.array(xyz_mm) * 1e-3
    pose = matrix_to_pose(T, rotation=rotation, length_scale=1e-3)
    np.testing.assert_allclose(pose[:3], xyz_mm, atol=1e-9)
    np.testing.assert_allclose(pose_to_matrix(pose, rotation=rotation, length_scale=1e-3), T,
                               atol=1e-9)


def test_pose_matches_jaka_units_example():
    # 100 mm along x, RPY (π, 0, -π/2) as in the JAKA ROS manual's example poses.
    T = pose_to_matrix([100, 0, 0, np.pi, 0, -np.pi / 2], rotation="rpy", length_scale=1e-3)
    np.testing.assert_allclose(T[:3, 3], [0.1, 0, 0])
    np.testing.assert_allclose(T[:3, :3] @ [0, 0, 1], [0, 0, -1], atol=1e-15)  # tool z down
    with pytest.raises(ValueError):
        pose_to_matrix([1, 2, 3], rotation="rpy")
    with pytest.raises(ValueError):
        matrix_to_pose(np.eye(4), rotation="euler")


@settings(max_examples=200, deadline=None)
@given(unit, angle, unit, angle, st.floats(0, 1))
def test_slerp_moves_a_fraction_of_the_angle(a0, t0, a1, t1, s):
    R0, R1 = rotvec_to_matrix(_rotvec(a0, t0)), rotvec_to_matrix(_rotvec(a1, t1))
    total = rotation_angle_between(R0, R1)
    Rs = slerp(R0, R1, s)
    _is_rotation(Rs)
    np.testing.assert_allclose(slerp(R0, R1, 0.0), R0, atol=1e-12)
    if total < np.pi - 1e-6:  # at exactly π "the shortest way" is not unique
        np.testing.assert_allclose(slerp(R0, R1, 1.0), R1, atol=1e-9)
        assert abs(rotation_angle_between(R0, Rs) - s * total) < 1e-9
        assert abs(rotation_angle_between(Rs, R1) - (1 - s) * total) < 1e-9


@settings(max_examples=200, deadline=None)
@given(unit, angle)
def test_rotation_angle_between_is_accurate_near_0_and_pi(axis, theta):
    R1 = rotvec_to_matrix(_rotvec(axis, theta))
    assert abs(rotation_angle_between(np.eye(3), R1) - theta) < 1e-12
    assert abs(rotation_angle_between(R1, np.eye(3)) - theta) < 1e-12


def test_stacks_keep_their_shape():
    rng = np.random.default_rng(0)
    rv = rng.normal(size=(4, 5, 3))
    rv *= (rng.uniform(0, 3.1, size=(4, 5, 1)) / np.linalg.norm(rv, axis=-1, keepdims=True))
    R = rotvec_to_matrix(rv)
    assert R.shape == (4, 5, 3, 3)
    np.testing.assert_allclose(matrix_to_rotvec(R), rv, atol=1e-12)
    np.testing.assert_allclose(quat_to_matrix(matrix_to_quat(R)), R, atol=1e-12)
    np.testing.assert_allclose(rpy_to_matrix(*np.moveaxis(matrix_to_rpy(R), -1, 0)), R, atol=1e-12)
    poses = np.concatenate([rng.normal(size=(7, 3)), rv[0, :, :].repeat(2, 0)[:7]], -1)
    np.testing.assert_allclose(matrix_to_pose(pose_to_matrix(poses)), poses, atol=1e-12)
    assert slerp(np.eye(3), R[0, 0], np.linspace(0, 1, 9)).shape == (9, 3, 3)
    assert rotation_angle_between(R[0], R[1]).shape == (5,)


def test_one_matrix_converts_exactly_as_a_stack_of_them():
    # the single-matrix path (plain floats, used for every state message) and the stacked
    # numpy path agree to rounding, also at 0 and at π
    rng = np.random.default_rng(7)
    v = rng.normal(size=(500, 3))
    v *= rng.uniform(0.0, np.pi, (500, 1)) / np.linalg.norm(v, axis=1, keepdims=True)
    v[:5] *= 1e-9
    v[5:10] *= np.pi / np.linalg.norm(v[5:10], axis=1, keepdims=True)
    R = rotvec_to_matrix(v)
    one_q = np.array([matrix_to_quat(r) for r in R])
    one_v = np.array([matrix_to_rotvec(r) for r in R])
    np.testing.assert_allclose(one_q, matrix_to_quat(R), atol=1e-15)
    np.testing.assert_allclose(one_v, matrix_to_rotvec(R), atol=1e-14)
