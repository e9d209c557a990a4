"""Every link of the twin meets every obstacle: only the base mount against link_1 and link_2
is left out of the contacts (they touch by construction). Before, the world body — floor and
every obstacle with it — was excluded against link_1 and link_2, and a Zu 5's joint move carried
its upper arm through a 40 mm box and answered "done".

The box stands where the Zu 5's upper arm passes as J2 swings from 90° to 54° (J1, J3… at
home): on the arm's axis at 72°, 0.33 m from the shoulder (J2's axis, 0.12 m above the base),
so that the arm's 60 mm-radius cylinder clears the box's nearest edge by 14 mm at both ends of
the swing (the arm meets it about 4° into the swing) and crosses it half way. In simulated time: the machine's load changes nothing.
"""
import numpy as np
import pytest

from support.sensor_twin import MODEL, fresh, twin_with_sensor

SHOULDER_Z = 0.12                    # m, J2's axis above the base (zu5 URDF)
REACH = 0.33                         # m along the upper arm
BOX_HALF = 0.02                      # m: a 40 mm box


def box_scene(path):
    angle = np.radians(90.0 - 72.0)  # the arm's tilt from vertical half way through the swing
    x, z = REACH * np.sin(angle), SHOULDER_Z + REACH * np.cos(angle)
    path.write_text(f"obstacles:\n  - {{name: box40, type: box, size: [{BOX_HALF}, {BOX_HALF}, "
                    f"{BOX_HALF}], pos: [{x:.4f}, 0.0, {z:.4f}]}}\n")
    return str(path)


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    scene = box_scene(tmp_path_factory.mktemp("scene") / "box40.yaml")
    with twin_with_sensor(scene, sensor=False) as d:
        yield d


@pytest.fixture
def arm(driver):
    yield from fresh(driver)


def j2_at(degrees):
    q = np.array(MODEL.home, float)
    q[1] = np.radians(degrees)
    return q.tolist()


def test_the_upper_arm_swinging_through_a_40_mm_box_is_stopped_by_the_collision(arm):
    assert arm.state().joint_position[1] == pytest.approx(np.radians(90.0), abs=1e-3)
    result = arm.joint_move(j2_at(54.0), 0.5, 2.0)
    st = arm.state()
    j2 = np.degrees(st.joint_position[1])
    print(f"joint_move: {result.code} {result.message!r}; J2 stopped at {j2:.1f}°")
    assert not result.ok, "the joint move went through the box and completed"
    assert "collision" in result.message and "box40" in result.message
    assert st.collision
    assert 80.0 < j2 < 89.0, "the arm should stop where it meets the box"


def test_the_same_swing_short_of_the_box_completes(arm):
    """The box alone does not stop the arm: a swing that ends 8 mm short of it is done."""
    result = arm.joint_move(j2_at(89.0), 0.5, 2.0)
    assert result.ok, result.message
    assert not arm.state().collision
