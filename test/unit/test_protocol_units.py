"""The unit edge of the protocol: deg ⇄ rad, wire poses (mm, RPY deg) ⇄ the protocol API's poses
(mm, RPY rad), and the chain the callers use to reach driver poses (mm, rotation vector rad,
through jaka_driver.common.transforms, R = Rz·Ry·Rx), including angle 0, angle π and pitch
±90°."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.common import transforms
from jaka_driver.protocol import units


def to_wire(pose_rotvec):
    """Driver pose (mm, rotation vector) → wire, the way the backend and the emulator do it."""
    p = np.asarray(pose_rotvec, float)
    rpy = transforms.matrix_to_rpy(transforms.rotvec_to_matrix(p[3:]))
    return units.pose_to_wire([*p[:3], *rpy])


def from_wire(wire):
    """Wire → driver pose (mm, rotation vector)."""
    p = units.pose_from_wire(wire)
    return np.concatenate([p[:3], transforms.matrix_to_rotvec(transforms.rpy_to_matrix(*p[3:]))])


# ---- independent reference maths (written differently from the module on purpose) ----------

def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def matrix_from_wire_rpy_deg(rpy_deg):
    r, p, y = np.radians(rpy_deg)
    return rz(y) @ ry(p) @ rx(r)


def matrix_from_rotvec(rv):
    """Via the unit quaternion, not Rodrigues."""
    rv = np.asarray(rv, float)
    angle = np.linalg.norm(rv)
    if angle == 0.0:
        return np.eye(3)
    x, y, z = rv / angle * math.sin(angle / 2)
    w = math.cos(angle / 2)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


# ---- strategies ----------------------------------------------------------------------------

unit_axes = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 1e-3).map(lambda v: v / np.linalg.norm(v))
special_angles = st.sampled_from([0.0, 1e-15, 1e-9, 1e-7, 1e-6, 1e-3, math.pi / 2,
                                  math.pi - 1e-3, math.pi - 1e-6, math.pi - 1e-9, math.pi])
angles = st.one_of(st.floats(0.0, math.pi), special_angles)
rotvecs = st.builds(lambda axis, angle: axis * angle, unit_axes, angles)
positions_mm = st.tuples(*[st.floats(-2000, 2000)] * 3)
special_pitch = st.sampled_from([90.0, -90.0, 90.0 - 1e-9, -90.0 + 1e-9, 89.999, -89.999])
rpy_deg = st.tuples(st.floats(-180, 180), st.one_of(st.floats(-90, 90), special_pitch),
                    st.floats(-180, 180))


# ---- joints --------------------------------------------------------------------------------

def test_joint_conversion_known_values():
    assert units.joints_to_wire([0, math.pi / 2, -math.pi, 0, 0, 2 * math.pi]) == \
        pytest.approx([0, 90, -180, 0, 0, 360])
    np.testing.assert_allclose(units.joints_from_wire([90, -45, 0, 0, 0, 180]),
                               [math.pi / 2, -math.pi / 4, 0, 0, 0, math.pi])


@given(st.lists(st.floats(-10, 10), min_size=6, max_size=6))
def test_joint_round_trip(q):
    wire = units.joints_to_wire(q)
    assert all(type(v) is float for v in wire)   # plain floats for JSON
    np.testing.assert_allclose(units.joints_from_wire(wire), q, atol=1e-12)


# ---- poses ---------------------------------------------------------------------------------

def test_pose_known_values():
    # quarter turn about z = yaw 90°
    assert to_wire([1, 2, 3, 0, 0, math.pi / 2]) == pytest.approx([1, 2, 3, 0, 0, 90])
    # rpy (90, 0, 0) - the flange at q = 0 (docs/models.md) - is a quarter turn about x
    np.testing.assert_allclose(from_wire([798.5, 7, 6.65, 90, 0, 0]),
                               [798.5, 7, 6.65, math.pi / 2, 0, 0], atol=1e-12)
    # half turn about x: roll ±180
    wire = to_wire([0, 0, 0, math.pi, 0, 0])
    assert abs(abs(wire[3]) - 180) < 1e-9 and abs(wire[4]) < 1e-9 and abs(wire[5]) < 1e-9


def test_rpy_order_is_z_then_y_then_x():
    wire_rpy = [30.0, 20.0, 10.0]
    rotvec = from_wire([0, 0, 0, *wire_rpy])[3:]
    np.testing.assert_allclose(matrix_from_rotvec(rotvec), matrix_from_wire_rpy_deg(wire_rpy),
                               atol=1e-12)


@settings(max_examples=300)
@given(positions_mm, rotvecs)
def test_driver_pose_round_trip(position, rotvec):
    pose = np.concatenate([position, rotvec])
    wire = to_wire(pose)
    assert all(type(v) is float for v in wire)
    # the wire angles describe the same rotation (checked with independent maths) ... to 1e-8:
    # at pitch ±90° (gimbal lock) roll and yaw come from atan2 of ~1e-9 entries, which costs
    # a few 1e-9 (hypothesis found rotvec (0, π/2, 3e-9)); JAKA's own resolution is 1e-3°
    np.testing.assert_allclose(matrix_from_wire_rpy_deg(wire[3:]), matrix_from_rotvec(rotvec),
                               atol=1e-8)
    assert -90 <= wire[4] <= 90 and -180 <= wire[3] <= 180 and -180 <= wire[5] <= 180
    back = from_wire(wire)
    np.testing.assert_allclose(back[:3], position, atol=1e-9)
    angle = np.linalg.norm(back[3:])
    assert angle <= math.pi + 1e-12
    # the same few 1e-9 at gimbal lock on the way back (hypothesis: rotvec (0, π/2, π·1e-9))
    np.testing.assert_allclose(matrix_from_rotvec(back[3:]), matrix_from_rotvec(rotvec),
                               atol=1e-8)
    if np.linalg.norm(rotvec) < math.pi - 1e-6:   # below π the rotation vector is unique
        np.testing.assert_allclose(back[3:], rotvec, atol=1e-8)


@settings(max_examples=300)
@given(positions_mm, rpy_deg)
def test_wire_pose_round_trip(position, rpy):
    back = to_wire(from_wire([*position, *rpy]))
    np.testing.assert_allclose(back[:3], position, atol=1e-9)
    # same rotation, also at pitch ±90° where roll and yaw are not separable
    np.testing.assert_allclose(matrix_from_wire_rpy_deg(back[3:]), matrix_from_wire_rpy_deg(rpy),
                               atol=1e-9)
    if abs(rpy[1]) < 89.9 and max(abs(rpy[0]), abs(rpy[2])) < 179.9:
        np.testing.assert_allclose(back[3:], rpy, atol=1e-7)


def test_tiny_rotation_keeps_precision():
    rv = np.array([1e-10, -2e-10, 3e-10])
    back = from_wire(to_wire([0, 0, 0, *rv]))[3:]
    np.testing.assert_allclose(back, rv, rtol=1e-6, atol=1e-20)


@pytest.mark.parametrize("pitch", [90.0, -90.0])
def test_gimbal_lock_is_exact(pitch):
    rpy = [25.0, pitch, -40.0]
    back = to_wire(from_wire([0, 0, 0, *rpy]))
    np.testing.assert_allclose(matrix_from_wire_rpy_deg(back[3:]), matrix_from_wire_rpy_deg(rpy),
                               atol=1e-12)
    assert back[4] == pytest.approx(pitch)


def test_protocol_api_pose_is_mm_and_rpy_radians():
    assert units.pose_to_wire([1, 2, 3, math.pi / 2, 0, -math.pi]) == \
        pytest.approx([1, 2, 3, 90, 0, -180])
    np.testing.assert_allclose(units.pose_from_wire([1, 2, 3, 90, -45, 180]),
                               [1, 2, 3, math.pi / 2, -math.pi / 4, math.pi])
