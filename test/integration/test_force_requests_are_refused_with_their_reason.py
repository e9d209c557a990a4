"""Every force request that cannot be served is refused with its reason, and changes nothing:
no sensor (-9, and how to mount one), the sensor off (-9), the arm in servo or drag mode (-9),
another motion (-10), a value outside its range (-2 naming the field, the value and the limit).
On the twin, in simulated time, through RobotDriver's door."""
import numpy as np
import pytest

from support.sensor_twin import MODEL, fresh, twin_with_sensor


@pytest.fixture(scope="module")
def driver():
    with twin_with_sensor() as d:
        yield d


@pytest.fixture
def arm(driver):
    yield from fresh(driver)


def test_an_arm_without_a_sensor_refuses_every_force_request_and_says_how_to_mount_one():
    with twin_with_sensor(sensor=False) as d:
        f = d.force
        for result in (f.sensor_enable(True), f.zero_sensor(), f.set_filter(5),
                       f.set_admittance(2, 1, 40, 0, 10), f.enable_tool_drive(True),
                       f.identify_payload([0.0] * 6), f.set_sensor_payload(1, [0, 0, 0]),
                       f.set_admittance(9, 1, -1, 0, 0),     # bad fields: no sensor still first
                       f.disable(), f.sensor_data(1)):
            assert result.code == -9, result
            assert "no force/torque sensor" in result.message
            assert "~force_sensor" in result.message and "force_sensor:=true" in result.message
        settings = f.settings()
        assert settings.ok and not settings.value.mounted
        assert d.state().force is None
        assert d.twin.push_tool([5, 0, 0, 0, 0, 0], 0.1).ok     # the hand needs no sensor


def test_the_sensor_off_refuses_what_needs_its_readings(arm):
    f = arm.force
    for result in (f.zero_sensor(), f.sensor_data(3), f.identify_payload(list(MODEL.home))):
        assert result.code == -9 and "sensor is off" in result.message, result
    assert f.set_admittance(2, 1, 40, 0, 10).ok          # settings may be made beforehand
    assert f.set_compliance_type(True, 1).ok
    result = f.enable_admittance(True)
    assert result.code == -9 and "sensor is off" in result.message, result
    assert f.settings().value.mode == "off"


def test_servo_and_drag_mode_refuse_force_control(arm):
    f = arm.force
    assert f.sensor_enable(True).ok
    assert f.set_admittance(2, 1, 40, 0, 10).ok and f.set_tool_drive(0, 1, 40, 0).ok
    assert arm.servo_move_enable(True).ok
    for result in (f.enable_admittance(True), f.enable_tool_drive(True),
                   f.identify_payload(list(MODEL.home))):
        assert result.code == -9 and "servo mode" in result.message, result
    assert arm.servo_move_enable(False).ok
    assert arm.drag_mode(True).ok
    for result in (f.enable_admittance(True), f.enable_tool_drive(True), f.zero_sensor()):
        assert result.code == -9 and "drag mode" in result.message, result
    assert arm.drag_mode(False).ok
    assert f.settings().value.mode == "off"


def test_force_control_is_refused_while_the_arm_moves_and_moves_while_it_runs(arm):
    f = arm.force
    assert f.sensor_enable(True).ok and f.set_tool_drive(0, 1, 40, 0).ok
    assert arm.jog(0, 0, 0.2).ok
    result = f.enable_tool_drive(True)
    assert result.code == -10 and "moves" in result.message, result
    assert arm.stop_move().ok
    arm.clock.sleep(0.3)
    assert f.enable_tool_drive(True).ok
    result = arm.joint_move(list(MODEL.home + 0.1), 1.0, 0)
    assert result.code == -10 and "force control holds the arm" in result.message, result
    result = f.identify_payload(list(MODEL.home))
    assert result.code == -10, result
    result = f.sensor_enable(False)
    assert result.code == -10 and "tool drive" in result.message, result
    assert f.disable().ok


@pytest.mark.parametrize("call, field, value, limit", [
    (lambda f: f.set_admittance(2, 1, 500.0, 0, 10), "ft_user", "500", "200"),
    (lambda f: f.set_admittance(2, 1, 40.0, 0, -250), "ft_constant", "-250", "200"),
    (lambda f: f.set_admittance(2, 1, 40.0, 25.0, 0), "rebound", "25", "20"),
    (lambda f: f.set_admittance(6, 1, 40.0, 0, 0), "axis", "6", "0–5"),
    (lambda f: f.set_admittance(2, 1, 40.0, 0, 0, 1), "normal_track", "1", "expected 0"),
    (lambda f: f.set_tool_drive(3, 1, 0.0, 0), "rigidity", "0", "10"),
    (lambda f: f.set_soft_limit([100, 100, 0, 5, 5, 5]), "soft limit Fz", "0", "200"),
    (lambda f: f.set_compliance_condition([0, 0, 300, 0, 0, 0]), "condition Fz", "300", "200"),
    (lambda f: f.set_filter(150.0), "cutoff", "150", "100"),
    (lambda f: f.set_velocity_compliance(2, [0.5, 0.6, 0.1, 0]), "rates[1]", "0.6", "0.5"),
    (lambda f: f.set_velocity_compliance(1, [0.5, 0.2, 0.1, 0]), "rates[2:]", "0.1", "0"),
    (lambda f: f.set_compliance_type(True, 3), "compliance_type", "3", "0–2"),
    (lambda f: f.set_frame(2), "frame", "2", "0–1"),
    (lambda f: f.set_sensor_payload(20.0, [0, 0, 50]), "mass", "20", "7.5"),
    (lambda f: f.identify_payload([0.0] * 7), "joint_positions", "7", "6 per pose"),
    (lambda f: f.sensor_data(0), "type", "0", "1–3"),    # JAKA numbers them 1–3
    (lambda f: f.sensor_data(4), "type", "4", "1–3"),
])
def test_a_value_outside_its_range_is_refused_naming_field_value_and_limit(arm, call, field,
                                                                        value, limit):
    f = arm.force
    assert f.sensor_enable(True).ok
    before = f.settings().value
    result = call(f)
    assert result.code == -2, result
    assert field in result.message and value in result.message and limit in result.message, \
        result.message
    after = f.settings().value
    assert after.admittance == before.admittance and after.tool_drive == before.tool_drive
    assert np.array_equal(after.soft_limit, before.soft_limit)
    assert np.array_equal(after.condition, before.condition)
    assert after.filter_hz == before.filter_hz and after.velocity == before.velocity
    assert after.tool_payload.mass == before.tool_payload.mass
