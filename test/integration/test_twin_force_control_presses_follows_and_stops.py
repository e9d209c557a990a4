"""Force control on the twin, in simulated time through RobotDriver's door, the arm at home over
the table of config/scenes/table.yaml (its top 3 mm below the probe's tip):

- constant force 10 N along the tool's z reaches 10 ± 0.5 N within 2 s of sim time and holds it,
  the probe never leaving the table once it touched (the unfiltered reading stays a press);
- tool drive follows a 20 N push along base x (it moves along the push, hardly across it) and
  stops once the push is released;
- admittance with a rebound springs back after the push;
- the compliance condition stops a move that presses harder than it allows (protective stop,
  -12 naming the condition), while a hard crash with no condition is still a collision and a
  press within the condition is not stopped.

Sampled every cycle (states_since); times are sim time, so the machine's load changes nothing.
"""
import numpy as np
import pytest

from jaka_driver.common.constants import SERVO_CYCLE
from jaka_driver.common.models import repo_root
from support.sensor_twin import MODEL, fresh, twin_with_sensor

TABLE = str(repo_root() / "config" / "scenes" / "table.yaml")


@pytest.fixture(scope="module")
def driver():
    with twin_with_sensor(TABLE) as d:
        yield d


@pytest.fixture
def arm(driver):
    """A fresh twin at home, its sensor on and zeroed there."""
    yield from fresh(driver, sensor_on=True, settle=0.2, zero=True)


def record(driver, seconds):
    """Every sample of the next ``seconds`` of sim time, oldest first."""
    samples, last = [], driver.state().stamp
    end = driver.clock.now() + seconds
    while driver.clock.now() < end:
        driver.clock.sleep(0.08)
        for st in driver.states_since(last):
            samples.append(st)
            last = st.stamp
    return samples


def test_constant_force_holds_10_n_on_the_table_within_2_s(arm):
    f = arm.force
    assert f.set_admittance(2, 1, 40.0, 0.0, 10.0).ok      # z: press 10 N, ft_user 40 N
    assert f.set_compliance_type(True, 1).ok
    t0 = arm.clock.now()
    assert f.enable_admittance(True).ok
    samples = record(arm, 3.0)
    t = np.array([s.stamp for s in samples]) - t0
    fz = np.array([s.force.actual[2] for s in samples])     # unfiltered: the sensor filter is off
    touched = int(np.argmax(fz < -1.0))
    assert fz[touched] < -1.0, "the probe never touched the table"
    outside = np.flatnonzero(np.abs(fz + 10.0) > 0.5)
    settled = t[outside[-1] + 1]
    print(f"touched at {t[touched]:.3f} s, within 10 ± 0.5 N from {settled:.3f} s; last second "
          f"{-fz[t > 2.0].mean():.3f} ± {fz[t > 2.0].std():.3f} N, min press after touching "
          f"{-fz[touched:].max():.2f} N")
    assert settled < 2.0
    assert np.all(fz[touched:] < -1.0), "contact was lost"
    assert np.all(np.abs(fz[t >= settled] + 10.0) <= 0.5)
    assert f.settings().value.mode == "constant_force"
    st = arm.state()
    assert not st.collision and not st.protective_stop      # 10 N is no crash
    assert f.disable().ok
    record(arm, 0.3)
    assert f.settings().value.mode == "off"


def test_tool_drive_follows_a_20_n_push_and_stops_when_released(arm):
    f = arm.force
    for axis in (0, 1, 2):
        assert f.set_tool_drive(axis, 1, 40.0, 0.0).ok       # 0.1 m/s at 40 N
    assert f.enable_tool_drive(True).ok
    assert arm.twin.push_tool([20.0, 0, 0, 0, 0, 0], 1.0).ok
    p0 = arm.state().tcp_pose[:3, 3].copy()
    pushed = record(arm, 1.0)
    p1 = pushed[-1].tcp_pose[:3, 3]
    after = record(arm, 1.0)
    speeds = [np.linalg.norm(s.joint_velocity) for s in after]
    rest = next(i for i, v in enumerate(speeds) if v < 1e-3 and
                max(speeds[i:]) < 1e-3)
    moved, drift = (p1 - p0) * 1000.0, (after[-1].tcp_pose[:3, 3] - p1) * 1000.0
    print(f"pushed 1 s: moved {np.round(moved, 2)} mm; at rest {rest * SERVO_CYCLE:.3f} s after "
          f"the release, {np.round(drift, 2)} mm further")
    assert moved[0] > 30.0                                  # along the push
    assert np.linalg.norm(moved[1:]) < 0.05 * moved[0]      # not across it
    assert rest * SERVO_CYCLE <= 0.5
    assert np.linalg.norm(drift) < 0.2 * moved[0]
    assert f.settings().value.mode == "tool_drive"


def test_admittance_with_a_rebound_springs_back_after_the_push(arm):
    f = arm.force
    assert f.set_admittance(1, 1, 40.0, 0.5, 0.0).ok         # y: 0.5 N/mm back to the start
    assert f.set_compliance_type(True, 0).ok
    assert f.enable_admittance(True).ok
    p0 = arm.state().tcp_pose[:3, 3].copy()
    assert arm.twin.push_tool([10.0, 0, 0, 0, 0, 0], 0.5).ok       # base x = the flange's -y here
    pushed = record(arm, 0.5)[-1].tcp_pose[:3, 3]
    back = record(arm, 2.0)[-1].tcp_pose[:3, 3]
    away, left = (pushed - p0)[0] * 1000.0, (back - p0)[0] * 1000.0
    print(f"pushed {away:.2f} mm along base x, {left:.2f} mm left after 2 s")
    assert away > 5.0
    assert abs(left) < 0.2 * away


def move_down(driver, mm, speed=20.0):
    pose = driver.get_fk(list(driver.state().joint_position)).value
    pose[2] -= mm
    return driver.linear_move(list(pose), speed, 0)


def test_the_compliance_condition_stops_a_move_that_presses_harder_than_it_allows(arm):
    f = arm.force
    assert f.set_compliance_condition([0, 0, 15.0, 0, 0, 0]).ok
    result = move_down(arm, 4.0)           # 1 mm into the table: ~30 N on its stiff top
    st = arm.state()
    print(f"pressing move: {result.code} {result.message}; at the stop Fz {st.force.actual[2]:.1f}"
          " N")
    assert result.code == -12 and "compliance condition" in result.message, result.message
    assert st.protective_stop and not st.collision
    assert arm.joint_move(list(MODEL.home), 1.0, 0).code == -12     # it stands until cleared
    assert arm.clear_err().ok


def test_a_press_within_the_condition_goes_on_and_a_crash_is_still_a_collision(arm):
    f = arm.force
    assert f.set_compliance_condition([0, 0, 15.0, 0, 0, 0]).ok
    assert move_down(arm, 3.2).ok          # touches, well under 15 N
    assert move_down(arm, -3.2).ok
    assert f.set_compliance_condition([0.0] * 6).ok
    result = move_down(arm, 20.0, speed=100.0)
    assert result.code == -12 and "collision" in result.message, result.message
    assert "ft_probe" in result.message and arm.state().collision
    assert arm.clear_err().ok


def test_velocity_compliance_slows_a_move_as_it_presses_towards_the_condition(arm):
    f = arm.force
    assert f.set_compliance_condition([0, 0, 24.0, 0, 0, 0]).ok     # bands of 8 N
    above = arm.get_fk(list(MODEL.home)).value                        # mm + rotvec

    def timed_press():
        target = list(above)
        # 0.5 mm into the table, ~14 N: more and the arm, deflected by the press, is not in
        # position at the end of the line (1e-3 rad)
        target[2] -= 3.6
        t0 = arm.clock.now()
        result = arm.linear_move(target, 2.0, 0)
        took = arm.clock.now() - t0
        pressed = -arm.state().force.actual[2]
        assert result.ok, result.message
        assert arm.joint_move(list(MODEL.home), 1.0, 0).ok
        return took, pressed

    plain, plain_press = timed_press()
    assert f.set_velocity_compliance(1, [0.3, 0.1, 0, 0]).ok      # 30 % above 8 N
    assert f.set_compliance_type(True, 2).ok
    assert f.enable_admittance(True).ok
    assert f.settings().value.mode == "velocity_compliance"
    slowed, slowed_press = timed_press()
    print(f"3.6 mm down at 2 mm/s: {plain:.3f} s pressing {plain_press:.1f} N; under velocity "
          f"compliance {slowed:.3f} s pressing {slowed_press:.1f} N")
    assert 8.0 < plain_press < 16.0 and 8.0 < slowed_press < 16.0      # into the second band
    # the last ~0.2 mm (0.1 s at 2 mm/s) at 30 % of the speed, reached in 0.11 s (a pace
    # changes by at most 0.05 a cycle): at least 0.1 s longer
    assert slowed > plain + 0.1
    assert f.disable().ok and f.settings().value.mode == "off"
