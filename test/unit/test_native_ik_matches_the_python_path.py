"""The compiled IK fast path (kinematics/jaka_ik.c) answers exactly what the Python path answers.

For every model (the Zu structure through the compiled closed form, the MiniCobo and A12
through the compiled damped least squares from the seed they start with), seeded targets over
the whole joint range — with and without a tool and a user frame — are solved twice, once through the library and once with it switched off: both
succeed on the same targets, with the same joints (to float rounding, 1e-9 rad), and the
library's answer is within tolerance by Pinocchio's FK. Bad input still gets the Python path's
refusal. ``make setup`` builds the library, so the suite requires it to be loaded.
"""
import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.common.transforms import pose_to_matrix
from jaka_driver.kinematics import Kinematics

N = 400


@pytest.fixture(scope="module", params=MODEL_NAMES)
def kin(request):
    return Kinematics(load_model(request.param))


def python_path(kin, *args, **kwargs):
    native, kin._native = kin._native, None
    try:
        return kin.ik(*args, **kwargs)
    finally:
        kin._native = native


def targets(kin, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(kin.model.lower, kin.model.upper, (N, 6))
    noisy = np.clip(q + rng.uniform(-0.2, 0.2, (N, 6)), kin.model.lower, kin.model.upper)
    return q, noisy


def test_the_library_is_built_and_loaded(kin):
    assert kin._native is not None, "devel/lib/libjaka_ik.so missing: run make setup"


@pytest.mark.parametrize("frames", ["flange", "tool and user"])
def test_same_solutions_as_the_python_path(kin, frames):
    tool = user = None
    if frames != "flange":
        tool = pose_to_matrix([0.01, -0.02, 0.12, 0.1, -0.2, 0.3])
        user = pose_to_matrix([0.4, 0.1, 0.05, 0.0, 0.0, 0.7])
    q_true, seeds = targets(kin, 11)
    solved = 0
    for q, seed in zip(q_true, seeds):
        T = kin.tcp_pose(q, tool, user)
        fast = kin.ik(T, seed=seed, tool=tool, user=user)
        slow = python_path(kin, T, seed=seed, tool=tool, user=user)
        assert fast.success == slow.success, (q, seed, fast.message, slow.message)
        if fast.success:
            solved += 1
            np.testing.assert_allclose(fast.q, slow.q, atol=1e-9)
            reached = kin.tcp_pose(fast.q, tool, user)
            assert np.max(np.abs(reached[:3, 3] - T[:3, 3])) < 1e-6
            assert np.max(np.abs(reached[:3, :3] - T[:3, :3])) < 1e-6
            assert np.all(fast.q >= kin.model.lower) and np.all(fast.q <= kin.model.upper)
    assert solved > 0.95 * N


def test_bad_input_is_still_refused_by_the_python_path(kin):
    T = kin.flange_pose(np.array([0.1, 1.5, -1.4, 1.5, 1.6, 0.2]))
    with pytest.raises(ValueError, match="joint positions"):
        kin.ik(T, seed=np.array([np.nan] * 6))
    with pytest.raises(ValueError, match="joint positions"):   # "finite" as Python counts it
        kin.ik(T, seed=np.array([1e200, 0, 0, 0, 0, 0]))
    bad = T.copy()
    bad[0, 3] = np.inf
    with pytest.raises(ValueError, match="target"):
        kin.ik(bad, seed=np.zeros(6))


def test_a_seed_outside_the_limits_is_clamped_like_the_python_path(kin):
    q = np.array([0.1, 1.5, -1.4, 1.5, 1.6, 0.2])
    T = kin.flange_pose(q)
    seed = q + np.array([0, 0, 0, 0, 0, 40.0])      # joint_6 far beyond its limit
    fast, slow = kin.ik(T, seed=seed), python_path(kin, T, seed=seed)
    assert fast.success == slow.success
    if fast.success:
        np.testing.assert_allclose(fast.q, slow.q, atol=1e-9)


def test_arrays_c_cannot_read_as_they_are_still_get_the_right_answer(kin):
    """Fortran-ordered, strided or read-only inputs are copied for C, never misread."""
    q = np.array([0.1, 1.5, -1.4, 1.5, 1.6, 0.2])
    T = kin.flange_pose(q)
    frozen = T.copy()
    frozen.setflags(write=False)
    strided = np.zeros((4, 8))
    strided[:, ::2] = T
    for target in (np.asfortranarray(T), frozen, strided[:, ::2]):
        r = kin.ik(target, seed=q)
        assert r.success
        np.testing.assert_allclose(r.q, q, atol=1e-8)
