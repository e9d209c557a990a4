"""A velocity jog looks at the arm once per 8 ms cycle, with the numbers the long way gives.

What it looks at — the TCP pose and the smallest singular value of the TCP's Jacobian
(:meth:`Kinematics.tcp_pose_and_sigma`) — matches Pinocchio's FK and numpy's SVD of
:meth:`Kinematics.jacobian` for every model, with and without a tool, through the compiled
library and without it (to 1e-11 m and 1e-11, the chains' rounding), near the wrist singularity
too. Its IK for one tool (:meth:`Kinematics.seeded_ik`) answers what :meth:`Kinematics.ik`
answers, entering C once. The step's end measured for the singularity check is the next cycle's
start: a jog whose steps are taken whole measures the arm once a cycle, one slowed by a
singularity twice (its setpoint is not the step's end).
"""
import numpy as np
import pytest

from jaka_driver.common.constants import MAX_TOOL_ROTATION_ACCEL, SERVO_CYCLE
from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.common.transforms import pose_to_matrix
from jaka_driver.kinematics import Kinematics
from jaka_driver.motion import velocity_jog

TOOL = pose_to_matrix([0.01, -0.02, 0.12, 0.1, -0.2, 0.3])
START = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0])


@pytest.fixture(scope="module", params=MODEL_NAMES)
def kin(request):
    return Kinematics(load_model(request.param))


def long_way(kin, q, tool):
    J = kin.jacobian(q, tool)
    return kin.tcp_pose(q, tool), np.linalg.svd(J, compute_uv=False)[-1]


@pytest.mark.parametrize("tool", [None, TOOL], ids=["flange", "tool"])
def test_pose_and_smallest_singular_value_match_fk_and_svd(kin, tool):
    rng = np.random.default_rng(5)
    native = kin._native
    for i in range(200):
        q = rng.uniform(kin.model.lower, kin.model.upper)
        if i % 20 == 0:
            q[4] = 1e-9                  # the wrist singularity (Zu: J5 at 0)
        pose, sigma = long_way(kin, q, tool)
        for compiled in (native, None):
            kin._native = compiled
            try:
                got_pose, got_sigma = kin.tcp_pose_and_sigma(q, tool)
            finally:
                kin._native = native
            assert np.max(np.abs(got_pose - pose)) < 1e-11
            assert abs(got_sigma - sigma) < 1e-11


@pytest.mark.parametrize("tool", [np.eye(4), TOOL], ids=["identity tool", "tool"])
def test_the_ik_of_one_tool_answers_as_ik(kin, tool):
    solve = kin.seeded_ik(tool)
    rng = np.random.default_rng(9)
    for _ in range(100):
        q = rng.uniform(kin.model.lower, kin.model.upper)
        seed = np.clip(q + rng.uniform(-0.05, 0.05, 6), kin.model.lower, kin.model.upper)
        target = kin.tcp_pose(q, tool)
        expected = kin.ik(target, seed=seed, tool=tool)
        got = solve(target, seed)
        assert (got is not None) == expected.success
        if got is not None:
            np.testing.assert_array_equal(got, expected.q)


def test_the_ik_of_one_tool_enters_c_once():
    kin = Kinematics(load_model("zu5"))
    calls = []
    lib = kin._native._lib

    class Counting:
        def __getattr__(self, name):
            function = getattr(lib, name)

            def counted(*args):
                result = function(*args)
                calls.append((name, result))
                return result
            return counted
    kin._native._lib = Counting()
    far = np.eye(4)
    far[:3, 3] = [3.0, 0.0, 0.2]         # m, out of reach: C fails, Python explains
    for tool in (np.eye(4), TOOL):
        solve = kin.seeded_ik(tool)
        for target in (kin.tcp_pose(START, tool), far):
            calls.clear()
            solve(target, START)
            assert len(calls) == 1, calls


def jog_on(kin, twist):
    """A jog of ``twist`` on ``kin``'s arm that records every joint vector it measured."""
    jog = velocity_jog.on_arm(kin, kin.model, np.eye(4), in_tool=False, ratio=1.0,
                              cycle=SERVO_CYCLE, angular_accel=MAX_TOOL_ROTATION_ACCEL)
    looks = []
    measure = jog._measure

    def recorded(q):
        looks.append(np.array(q, float))
        return measure(q)
    jog._measure = recorded
    jog.command(np.asarray(twist, float))
    return jog, looks


def test_a_jog_taken_whole_measures_the_arm_once_a_cycle():
    kin = Kinematics(load_model("zu5"))
    jog, looks = jog_on(kin, [0.05, 0.0, 0.0, 0.0, 0.0, 0.0])
    q = START.copy()
    for k in range(100):
        q = jog.next(q.copy())          # a copy, as the twin's drives hand the setpoint back
        assert jog.limited_by is None
        assert len(looks) == k + 2      # the first cycle measures its start too
        np.testing.assert_array_equal(looks[-1], q)    # the step's end is the setpoint


def test_a_step_slowed_near_a_singularity_measures_its_setpoint_the_next_cycle():
    """Each cycle starts from a measurement of exactly its setpoint: last cycle's end when
    the step was taken whole (one look this cycle), else a new one (two looks)."""
    kin = Kinematics(load_model("zu5"))
    q = START.copy()
    q[4] = 0.3                           # the wrist 0.3 rad from straight: σ_min 0.075
    jog, looks = jog_on(kin, [0.0, -0.01, 0.03, -0.3, 0.0, 0.0])   # J5 towards 0
    last_end, slowed, whole = None, 0, 0
    for _ in range(150):
        start, before = q.copy(), len(looks)
        q = jog.next(start)
        new = looks[before:]
        if not new:
            continue                     # held at rest: nothing measured
        if last_end is not None and np.array_equal(last_end, start):
            assert len(new) == 1
            whole += 1
        else:
            assert len(new) == 2
            np.testing.assert_array_equal(new[0], start)
        last_end = new[-1]
        slowed += jog.limited_by is not None and "singularity" in jog.limited_by
    assert slowed > 10 and whole > 10
    assert kin.tcp_pose_and_sigma(q)[1] > velocity_jog.SINGULAR_STOP   # stopped short of it
