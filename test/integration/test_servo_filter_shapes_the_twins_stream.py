"""A servo filter chosen through RobotDriver shapes what the twin's drives follow (servo_j,
servo_p and the joint stream topics share the path): with the joint low-pass of 2 Hz a held
step is a first-order lag (63 % after τ = 80 ms, not at once), the Cartesian non-linear filter
holds the TCP within its speed; the filter is refused in servo mode and shown in the twin's
description (/diagnostics)."""
import numpy as np
import pytest

from support.twin_samples import collected_twin

from jaka_driver.common.models import load_model
from jaka_driver.common.results import Code
from jaka_driver.common.transforms import matrix_to_rpy

MODEL = load_model("zu5")


@pytest.fixture(scope="module")
def twin():
    yield from collected_twin(MODEL)


@pytest.fixture
def fresh(twin):
    assert twin.twin.reset().ok
    return twin


def hold_target(driver, send, cycles):
    """Send the same target ``cycles`` times, one per 8 ms cycle, in servo mode; the sim time
    the stream began."""
    clock = driver.clock
    with clock.hold():
        assert driver.servo_move_enable(True).ok
        t0 = clock.now()
        for _ in range(cycles):
            assert send().ok
            clock.sleep(0.008)
        assert driver.servo_move_enable(False).ok
    return t0


def test_the_joint_low_pass_makes_a_held_step_a_first_order_lag(fresh):
    assert fresh.set_servo_filter(1, lpf_cutoff_hz=2.0).ok
    assert fresh.backend.describe()["servo_filter"] == "joint low-pass (cut-off 2 Hz)"
    q0 = fresh.state().joint_position.copy()
    target = q0 + np.array([0, 0, 0, 0, 0, 0.02])
    t0 = hold_target(fresh, lambda: fresh.servo_j(target), 60)
    q6 = np.array([st.joint_position[5] - q0[5]
                   for st in fresh.samples.since(t0, fresh.state().stamp)])
    assert q6[2] < 0.02 * 0.3                       # not at once (unfiltered: 2 cycles)
    assert 0.02 * 0.5 < q6[12] < 0.02 * 0.8         # ~63 % after ~80 ms (+ the drive's lag)
    assert q6[-1] == pytest.approx(0.02, abs=0.001)
    assert fresh.set_servo_filter(0).ok


def test_the_cartesian_nonlinear_filter_holds_the_tcp_within_its_speed(fresh):
    assert fresh.set_servo_filter(4, nlf_max_vp=50, nlf_max_ap=500, nlf_max_jp=5000,
                                  nlf_max_vr=1, nlf_max_ar=5, nlf_max_jr=50).ok
    start = fresh.state().tcp_pose.copy()
    target = np.concatenate([start[:3, 3] + [0.0, 0.0, -0.004], matrix_to_rpy(start[:3, :3])])
    # servo_p's step check allows 4 mm in one cycle only at 500 mm/s: well within the zu5's
    t0 = hold_target(fresh, lambda: fresh.servo_p(target), 80)
    z = np.array([st.tcp_pose[2, 3] for st in fresh.samples.since(t0, fresh.state().stamp)])
    speed = np.abs(np.diff(z)) / 0.008
    assert speed.max() < 0.050 * 1.2                 # 50 mm/s (+ the drives' following)
    assert z[-1] == pytest.approx(start[2, 3] - 0.004, abs=1e-4)
    assert fresh.set_servo_filter(0).ok


def test_a_filter_is_refused_in_servo_mode_and_out_of_range(fresh):
    assert fresh.servo_move_enable(True).ok
    refused = fresh.set_servo_filter(1, lpf_cutoff_hz=2.0)
    assert refused.code == Code.WRONG_MODE and "servo mode" in refused.message
    assert fresh.servo_move_enable(False).ok
    out = fresh.set_servo_filter(3, mmf_buffer=500, mmf_kp=1)
    assert out.code == Code.INVALID_PARAMETER and "mmf_buffer is 500" in out.message
