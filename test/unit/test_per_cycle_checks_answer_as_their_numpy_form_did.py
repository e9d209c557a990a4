"""The checks every servo target and status packet passes, now asked in plain Python
(jaka_driver.common.joint_limits, common.values.all_finite, protocol.wire.float_vector), give
the answers of their numpy form — written out here as numpy says it — for targets inside, on and
past the limits, steps at and past the speed limit, ties, infinities and NaN, on every arm."""
from typing import Optional

import numpy as np
import pytest

from jaka_driver.common import MODEL_NAMES, load_model
from jaka_driver.common.joint_limits import (ON_LIMIT_MARGIN, fastest_step, on_limit,
                                             outside_limits)

CYCLE = 0.008


def outside_by_arrays(model, q, tolerance=0.0) -> Optional[int]:
    outside = (q < model.lower - tolerance) | (q > model.upper + tolerance)
    return int(np.argmax(outside)) if outside.any() else None


def on_limit_by_arrays(model, q) -> bool:
    q = np.asarray(q, float)
    return bool(np.any((q <= model.lower + ON_LIMIT_MARGIN) | (q >= model.upper - ON_LIMIT_MARGIN)))


def fastest_by_arrays(model, q_from, q_to, seconds=CYCLE):
    step = np.abs(np.asarray(q_to) - np.asarray(q_from)) / seconds
    worst = int(np.argmax(step / model.max_velocity))
    return (worst, float(step[worst])) if step[worst] > model.max_velocity[worst] else None


def targets(model, rng, n=400) -> list[np.ndarray]:
    """Random targets across and beyond the limits, and the edges exactly."""
    span = model.upper - model.lower
    out = [model.lower + rng.uniform(-0.1, 1.1, 6) * span for _ in range(n)]
    out += [model.lower.copy(), model.upper.copy(), model.lower + ON_LIMIT_MARGIN,
            model.upper - ON_LIMIT_MARGIN, np.nextafter(model.upper, np.inf),
            np.nextafter(model.lower, -np.inf)]
    special = model.home.copy()
    special[2] = np.nan
    out.append(special)
    special = model.home.copy()
    special[4] = np.inf
    out.append(special)
    return out


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_position_limits_answer_as_the_array_form(name):
    model = load_model(name)
    rng = np.random.default_rng(7)
    for q in targets(model, rng):
        for tolerance in (0.0, 1e-9):
            assert outside_limits(model, q, tolerance) == outside_by_arrays(model, q, tolerance)
        assert outside_limits(model, list(q)) == outside_by_arrays(model, q)
        assert on_limit(model, q) is on_limit_by_arrays(model, q)
        assert on_limit(model, list(q)) is on_limit_by_arrays(model, q)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_speed_limits_answer_as_the_array_form(name):
    model = load_model(name)
    rng = np.random.default_rng(11)
    limit_step = model.max_velocity * CYCLE
    starts = [model.home + rng.uniform(-0.5, 0.5, 6) for _ in range(200)]
    for q0 in starts:
        for step in (rng.uniform(-1.5, 1.5, 6) * limit_step,     # some past the limit
                     limit_step.copy(),                           # each exactly at its limit
                     np.full(6, 0.0),
                     np.where(np.arange(6) % 2 == 0, 2.0, 0.5) * limit_step,   # a tie at 2×
                     np.where(np.arange(6) == 3, np.inf, 0.0),
                     np.where(np.arange(6) == 1, np.nan, 3.0) * limit_step):
            q1 = q0 + step
            assert fastest_step(model, q0, q1) == fastest_by_arrays(model, q0, q1)
            assert fastest_step(model, list(q0), list(q1), 3 * CYCLE) == \
                fastest_by_arrays(model, q0, q1, 3 * CYCLE)


def test_a_tie_names_the_first_joint_and_its_speed():
    model = load_model("zu5")                           # every joint's limit is 3.14 rad/s
    q0 = np.zeros(6)
    q1 = q0 + 2.0 * model.max_velocity * CYCLE          # every joint at twice its limit
    joint, speed = fastest_step(model, q0, q1)
    assert joint == 0
    assert speed == pytest.approx(2.0 * 3.14, rel=1e-12)


@pytest.mark.parametrize("values, finite", [
    (np.zeros(6), True), (np.full(6, 1e308), True), (np.eye(4), True),
    (np.array([0, 0, np.nan, 0, 0, 0]), False), (np.array([np.inf]), False),
    (np.array([[0.0, -np.inf], [0.0, 0.0]]), False), ([1, 2, 3], True), (np.zeros(0), True)])
def test_all_finite_answers_as_numpys_isfinite_all(values, finite):
    from jaka_driver.common.values import all_finite
    assert all_finite(values) is finite is bool(np.all(np.isfinite(values)))


@pytest.mark.parametrize("value, n, expected", [
    ([1, 2, 3], 3, [1.0, 2.0, 3.0]), ([1, 2], 3, None), ([1, float("nan"), 3], 3, None),
    ([1, float("inf"), 3], 3, None), ("abc", 3, None), ([[1, 2, 3]], 3, None), (None, 3, None)])
def test_a_packets_vector_is_n_finite_floats_or_none(value, n, expected):
    from jaka_driver.protocol.wire import float_vector
    got = float_vector(value, n)
    assert (got is None) if expected is None else got.tolist() == expected
