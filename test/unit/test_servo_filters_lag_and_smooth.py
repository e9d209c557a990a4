"""The six servo filters on a step and a sine, per 8 ms cycle: each one's lag and smoothing in
numbers — the low-pass as its closed form says, the non-linear filters within their velocity,
acceleration and jerk limits and without overshoot, the multi-order mean's exact ramp lag and
weight ratios, the speed foresight without lag on a ramp and without overshoot on a step — and
the ranges a request is checked against (-2 naming field, value and range)."""
import math

import numpy as np
import pytest

from gantry_arm import gantry_fk, gantry_ik, pose
from jaka_driver.common.models import load_model
from jaka_driver.common.results import CommandRefused
from jaka_driver.motion.servo_filters import (CartesianNonlinear, FilterType, JointLowPass,
                                              JointMultiOrderMean, JointNonlinear, NoFilter,
                                              SpeedForesight, checked_spec, make_filter)

T = 0.008
N = 1200
STEP = np.r_[0.0, np.full(N - 1, 0.1)]                         # 0.1 rad at cycle 1
SINE = 0.05 * np.sin(2 * math.pi * 0.5 * np.arange(N) * T)      # 0.5 Hz, ±0.05 rad
RAMP = 0.2 * np.arange(N) * T                                   # 0.2 rad/s


def run(f, xs):
    f.reset(np.array([xs[0]]))
    return np.array([f.next(np.array([x]))[0] for x in xs])


def lag(out, xs, start=300, span=500):
    """Cycles by which ``out`` follows ``xs`` best."""
    return min(range(100), key=lambda d: np.mean((out[start + d:start + d + span]
                                                  - xs[start:start + span]) ** 2))


def amplitude(out, xs, start=300):
    return np.ptp(out[start:]) / np.ptp(xs[start:])


def peak_accel(out):
    return np.abs(np.diff(out, 2)).max() / T ** 2


def test_no_filter_passes_the_target_as_it_came():
    assert np.array_equal(run(NoFilter(), STEP), STEP)


def test_low_pass_is_the_first_order_lag_of_its_cut_off():
    fc = 2.0
    tau = 1 / (2 * math.pi * fc)                                # 79.6 ms
    out = run(JointLowPass(fc, T), STEP)
    k63 = np.argmax(out >= 0.1 * (1 - math.exp(-1)))
    assert abs(k63 * T - tau) <= T                              # 63 % after τ
    assert out.max() <= 0.1 and np.all(np.diff(out) >= 0)      # no overshoot
    assert peak_accel(out) < peak_accel(STEP) / 50              # smoothed
    sine = run(JointLowPass(fc, T), SINE)
    expected = math.atan(0.5 / fc) / (2 * math.pi * 0.5)       # 78 ms
    assert abs(lag(sine, SINE) * T - expected) <= T
    assert amplitude(sine, SINE) == pytest.approx(1 / math.sqrt(1 + (0.5 / fc) ** 2),
                                                  abs=0.01)


def test_joint_nonlinear_keeps_its_limits_and_does_not_overshoot():
    v, a, j = 1.0, 4.0, 40.0
    f = JointNonlinear(v, a, j, T)
    f.reset(np.zeros(1))
    out, vel, acc = [], [], []
    for x in STEP[1:]:
        out.append(f.next(np.array([x]))[0])
        vel.append(f._tracker.velocity[0])
        acc.append(f._tracker.accel[0])
    out, vel, acc = map(np.array, (out, vel, acc))
    # there; no overshoot beyond a cycle's largest jerk step (J·T³ = 2e-5 rad here)
    assert out.max() - 0.1 <= j * T ** 3 and out[-1] == 0.1
    assert np.abs(vel).max() <= v * 1.001                       # within its velocity
    assert np.abs(acc).max() <= a + 1e-12
    landed = np.argmax(out == 0.1)
    assert np.abs(np.diff(acc[:landed])).max() / T <= j * 1.001  # and jerk, until it lands
    # as soon as the time-optimal S-curve (rest to rest, 0.1 rad, v not reached, a reached:
    # acceleration phase (a²/j + √(a⁴/j² + 4·d·a)) / 2a, twice) to within two cycles
    t_optimal = 2 * (a * a / j + math.sqrt(a ** 4 / j ** 2 + 4 * 0.1 * a)) / (2 * a)  # 0.43 s
    assert abs((landed + 1) * T - t_optimal) <= 2 * T
    sine = run(JointNonlinear(v, a, j, T), SINE)
    assert 3 <= lag(sine, SINE) <= 12                           # 56 ms measured
    assert amplitude(sine, SINE) == pytest.approx(1.0, abs=0.01)


def test_joint_nonlinear_follows_a_target_that_goes_down_as_well_as_up():
    out = run(JointNonlinear(1.0, 4.0, 40.0, T), -STEP)
    assert out.min() >= -0.1 - 40.0 * T ** 3 and out[-1] == -0.1


def test_multi_order_mean_lags_a_ramp_by_its_weighted_delay_and_never_overshoots():
    n = 10
    out = run(JointMultiOrderMean(n, 1, 2, 1), STEP)
    assert np.all(np.diff(out) >= -1e-15) and out.max() <= 0.1 + 1e-15
    assert np.argmax(out >= 0.1 - 1e-12) == 3 * (n - 1) + 1   # through three means
    assert peak_accel(out) < peak_accel(STEP) / 30
    ramp = run(JointMultiOrderMean(n, 1, 2, 1), RAMP)
    behind = (RAMP[200:] - ramp[200:]) / (0.2 * T)              # cycles
    expected = (1 + 2 * 2 + 3 * 1) / 4 * (n - 1) / 2           # 9 cycles
    np.testing.assert_allclose(behind, expected, atol=1e-6)
    sine = run(JointMultiOrderMean(n, 1, 2, 1), SINE)
    assert abs(lag(sine, SINE) - expected) <= 1
    assert amplitude(sine, SINE) > 0.98


def test_multi_order_mean_reads_only_the_ratio_of_its_weights():
    a = run(JointMultiOrderMean(20, 0.2, 0.4, 0.2), SINE)
    b = run(JointMultiOrderMean(20, 2, 4, 2), SINE)
    np.testing.assert_allclose(a, b, atol=1e-15)


def test_speed_foresight_does_not_lag_a_ramp_or_overshoot_a_step():
    n, kp = 10, 0.2
    ramp = run(SpeedForesight(n, kp), RAMP)
    behind = (RAMP[200:] - ramp[200:]) / (0.2 * T)
    np.testing.assert_allclose(behind, 0.0, atol=1e-6)          # none, against MMF's 9
    out = run(SpeedForesight(n, kp), STEP)
    assert out.max() <= 0.1 + 1e-15 and np.all(np.diff(out) >= -1e-15)
    assert np.argmax(out >= 0.09) * T < 0.1                     # 90 % in 72 ms
    assert peak_accel(out) < peak_accel(STEP) / 10
    sine = run(SpeedForesight(n, kp), SINE)
    assert lag(sine, SINE) <= 1
    assert amplitude(sine, SINE) == pytest.approx(1.0, abs=0.01)


def test_speed_foresight_with_a_smaller_kp_is_smoother_on_noisy_targets():
    noisy = SINE + np.random.default_rng(7).normal(0.0, 0.002, N)

    def roughness(kp):
        out = run(SpeedForesight(10, kp), noisy)
        return np.sqrt(np.mean(np.diff(out[100:], 2) ** 2))
    assert roughness(0.05) < roughness(0.5) < roughness(1.0) < np.sqrt(np.mean(
        np.diff(noisy[100:], 2) ** 2))


def test_cartesian_nonlinear_limits_the_tcp_and_passes_joint_targets():
    f = CartesianNonlinear((0.1, 0.5, 5.0), (0.5, 2.0, 20.0), T, gantry_ik, gantry_fk)
    q0 = gantry_ik(pose([0.4, 0.0, 0.3]), None)
    f.reset(q0)
    goal = pose([0.45, 0.0, 0.3], [0.0, 0.0, 0.2])              # 50 mm and 0.2 rad away
    qs = np.array([f.next(q0, goal) for _ in range(250)])
    p = qs[:, :3]
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1) / T
    assert speed.max() <= 0.1 * 1.001 and p[:, 0].max() <= 0.45 + 1e-6
    np.testing.assert_allclose(gantry_fk(qs[-1]), goal, atol=1e-9)
    turn = np.abs(np.diff(qs[:, 5])) / T
    assert turn.max() <= 0.5 * 1.001
    assert np.array_equal(f.next(q0 + 0.01), q0 + 0.01)         # servo_j: unfiltered
    assert f.failures == 0


MODEL = load_model("zu5")


@pytest.mark.parametrize("filter_type, params, message", [
    (6, {}, "filter_type is 6, expected 0–5"),
    (1, {"lpf_cutoff_hz": 0.0}, "lpf_cutoff_hz is 0 Hz, expected [0.01, 62.5] Hz"),
    (1, {"lpf_cutoff_hz": 100.0}, "lpf_cutoff_hz is 100 Hz, expected [0.01, 62.5] Hz"),
    (2, {"nlf_max_vr": 40.0, "nlf_max_ar": 1, "nlf_max_jr": 1}, "nlf_max_vr is 40 rad/s, "
     "expected (0, 31.4] rad/s"),
    (2, {"nlf_max_vr": 1.0, "nlf_max_ar": 0.0, "nlf_max_jr": 1}, "nlf_max_ar is 0 rad/s²"),
    (4, {"nlf_max_vr": 1, "nlf_max_ar": 1, "nlf_max_jr": 1, "nlf_max_vp": 50000,
         "nlf_max_ap": 1, "nlf_max_jp": 1}, "nlf_max_vp is 50000 mm/s, expected (0, "),
    (3, {"mmf_buffer": 0, "mmf_kp": 1}, "mmf_buffer is 0, expected a whole number 1–200"),
    (3, {"mmf_buffer": 2.5, "mmf_kp": 1}, "mmf_buffer is 2.5"),
    (3, {"mmf_buffer": 10}, "mmf_kp, mmf_kv and mmf_ka are all 0"),
    (3, {"mmf_buffer": 10, "mmf_kp": -1}, "mmf_kp is -1, expected [0, 1000]"),
    (5, {"mmf_buffer": 10, "mmf_kp": 0}, "mmf_kp is 0, expected (0, 1000]"),
])
def test_a_parameter_out_of_its_range_is_refused_with_field_value_and_range(filter_type,
                                                                           params, message):
    with pytest.raises(CommandRefused) as refused:
        checked_spec(MODEL, filter_type, params)
    assert refused.value.code == -2
    assert message in refused.value.message


def test_a_checked_spec_makes_its_filter_and_says_what_it_is():
    spec = checked_spec(MODEL, 4, {"nlf_max_vp": 100, "nlf_max_ap": 500, "nlf_max_jp": 5000,
                                   "nlf_max_vr": 1, "nlf_max_ar": 2, "nlf_max_jr": 20,
                                   "lpf_cutoff_hz": 99})       # another filter's: not read
    assert spec.type == FilterType.CARTESIAN_NLF and spec.linear_velocity == 0.1
    assert spec.describe() == ("Cartesian non-linear (100 mm/s, 500 mm/s², 5000 mm/s³; "
                               "1 rad/s, 2 rad/s², 20 rad/s³)")
    f = make_filter(spec, T, gantry_ik, gantry_fk)
    assert isinstance(f, CartesianNonlinear)
    assert checked_spec(MODEL, 0, {}).describe() == "none"
    assert checked_spec(MODEL, 5, {"mmf_buffer": 15, "mmf_kp": 0.03}).describe() == \
        "speed foresight (buffer 15, kp 0.03)"


@pytest.mark.parametrize("filter_type, params", [
    (1, {"lpf_cutoff_hz": 0.5}),                         # JAKA's MoveIt server
    (5, {"mmf_buffer": 15, "mmf_kp": 0.03}),             # JAKA's ROS node
    (5, {"mmf_buffer": 200, "mmf_kp": 2}),               # JAKA's examples: kp 2, buffers to 200
    (3, {"mmf_buffer": 20, "mmf_kp": 2, "mmf_kv": 4, "mmf_ka": 2}),
    (4, {"nlf_max_vp": 50, "nlf_max_ap": 200, "nlf_max_jp": 800,    # carte_NLF(50, 200, 800,
         "nlf_max_vr": math.radians(30), "nlf_max_ar": math.radians(60),   # 30, 60, 100)
         "nlf_max_jr": math.radians(100)}),
    (2, {"nlf_max_vr": math.radians(360), "nlf_max_ar": math.radians(720),  # above the arm's
         "nlf_max_jr": math.radians(1440)}),                                # own: not binding
])
def test_the_values_jakas_examples_send_are_accepted(filter_type, params):
    assert checked_spec(MODEL, filter_type, params).type == filter_type
