"""FK, Jacobian and IK of every Zu model agree with each other and find the seed's configuration."""
import threading
from dataclasses import replace

import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.common.transforms import pose_to_matrix, rotation_angle_between, rotvec_to_matrix
from jaka_driver.kinematics import IkResult, Kinematics


@pytest.fixture(scope="module", params=MODEL_NAMES)
def kin(request):
    return Kinematics(load_model(request.param))


def _random_q(kin, rng, n):
    return rng.uniform(kin.model.lower, kin.model.upper, (n, 6))


def _random_frame(rng, scale):
    return pose_to_matrix(np.r_[rng.uniform(-scale, scale, 3), rng.uniform(-1.5, 1.5, 3)])


def _well_conditioned(kin, q, tool=None):
    """Away from singularities, where the seed's branch is well separated from the others."""
    return np.linalg.svd(kin.jacobian(q, tool), compute_uv=False)[-1] > 0.008


def test_flange_pose_and_tcp_pose_compose_tool_and_user(kin):
    rng = np.random.default_rng(1)
    tool, user = _random_frame(rng, 0.2), _random_frame(rng, 0.5)
    for q in _random_q(kin, rng, 10):
        F = kin.flange_pose(q)
        np.testing.assert_allclose(F[3], [0, 0, 0, 1])
        np.testing.assert_allclose(kin.tcp_pose(q), F)
        np.testing.assert_allclose(kin.tcp_pose(q, tool, user), np.linalg.inv(user) @ F @ tool,
                                   atol=1e-12)


def test_tcp_pose_follows_every_change_of_the_user_frame():
    """The user frame's inverse is kept between calls: a new frame, the old one again, the
    same array changed in place and a frame that is no pose must all be seen."""
    kin = Kinematics(load_model("zu5"))
    rng = np.random.default_rng(2)
    q, tool = _random_q(kin, rng, 1)[0], _random_frame(rng, 0.2)
    F = kin.flange_pose(q)
    a, b = _random_frame(rng, 0.5), _random_frame(rng, 0.5)
    for user in (a, b, a, a.copy()):
        np.testing.assert_allclose(kin.tcp_pose(q, tool, user), np.linalg.inv(user) @ F @ tool,
                                   atol=1e-12)
    a[:3, 3] += 0.1                            # the same array, moved
    np.testing.assert_allclose(kin.tcp_pose(q, tool, a), np.linalg.inv(a) @ F @ tool,
                               atol=1e-12)
    np.testing.assert_allclose(kin.tcp_pose(q, tool, a.tolist()), np.linalg.inv(a) @ F @ tool,
                               atol=1e-12)
    bad = a.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError):
        kin.tcp_pose(q, tool, bad)
    with pytest.raises(ValueError):
        kin.tcp_pose(q, tool, a.reshape(16))   # the same bytes, not a 4x4


def test_jacobian_matches_finite_differences(kin):
    rng = np.random.default_rng(2)
    tool = _random_frame(rng, 0.15)
    h = 1e-6
    for q in _random_q(kin, rng, 10):
        for t in (tool, None):
            J = kin.jacobian(q, t)  # first, so no earlier FK of q can hide a stale frame
            T0 = kin.tcp_pose(q, t)
            num = np.empty((6, 6))
            for j in range(6):
                dq = np.zeros(6)
                dq[j] = h
                T1 = kin.tcp_pose(q + dq, t)
                num[:3, j] = (T1[:3, 3] - T0[:3, 3]) / h
                W = (T1[:3, :3] @ T0[:3, :3].T - np.eye(3)) / h  # skew(ω) in base axes
                num[3:, j] = [W[2, 1], W[0, 2], W[1, 0]]
            np.testing.assert_allclose(J, num, atol=2e-5)


def test_seeded_ik_returns_the_seeds_configuration(kin):
    rng = np.random.default_rng(3)
    checked = 0
    for q in _random_q(kin, rng, 500):
        if not _well_conditioned(kin, q):
            continue
        seed = q + rng.normal(0.0, 0.01, 6)
        r = kin.ik(kin.flange_pose(q), seed=seed)
        assert r.success, r.message
        np.testing.assert_allclose(r.q, q, atol=1e-6)
        assert r.position_error <= 1e-6 and r.rotation_error <= 1e-6
        checked += 1
    assert checked > 350  # ~85 % of random configurations


def test_seeded_ik_with_user_and_tool_frames(kin):
    rng = np.random.default_rng(4)
    tool, user = _random_frame(rng, 0.2), _random_frame(rng, 0.5)
    checked = 0
    for q in _random_q(kin, rng, 100):
        if not _well_conditioned(kin, q, tool):
            continue
        target = kin.tcp_pose(q, tool, user)
        r = kin.ik(target, seed=q + rng.normal(0.0, 0.01, 6), tool=tool, user=user)
        assert r.success, r.message
        np.testing.assert_allclose(r.q, q, atol=1e-6)
        T = kin.tcp_pose(r.q, tool, user)
        assert np.linalg.norm(T[:3, 3] - target[:3, 3]) <= 1e-6
        assert rotation_angle_between(T[:3, :3], target[:3, :3]) <= 1e-6
        checked += 1
    assert checked > 60


def test_unseeded_ik_succeeds_and_prefers_the_middle_of_the_limits(kin):
    rng = np.random.default_rng(5)
    qs = _random_q(kin, rng, 200)
    ok = 0
    for q in qs:
        target = kin.flange_pose(q)
        r = kin.ik(target)
        if not r.success:
            continue
        ok += 1
        assert np.all(r.q >= kin.model.lower) and np.all(r.q <= kin.model.upper)
        np.testing.assert_allclose(kin.flange_pose(r.q), target, atol=2e-6)
        mid = 0.5 * (kin.model.lower + kin.model.upper)
        others = kin.ik_all(target)
        w = 1.0 / kin.model.max_velocity
        # branches are ranked by the ideal chain's solutions, ~1e-2 rad from the exact ones on
        # the models with sub-mm offsets: two branches within that of each other tie
        assert np.sum(((r.q - mid) * w) ** 2) <= 1.02 * min(np.sum(((o - mid) * w) ** 2)
                                                            for o in others) + 1e-9
    assert ok >= 198
    assert kin.ik(kin.flange_pose(qs[0])).q.tolist() == kin.ik(kin.flange_pose(qs[0])).q.tolist()


def test_ik_all_lists_distinct_exact_solutions(kin):
    rng = np.random.default_rng(6)
    for q in _random_q(kin, rng, 20):
        target = kin.flange_pose(q)
        sols = kin.ik_all(target, reference=q)
        # a general 6R arm has up to 16 solutions; the Zu and spherical-wrist layouts up to 8
        assert 1 <= len(sols) <= (8 if kin.model.structure != "forearm_roll" else 16)
        if _well_conditioned(kin, q):
            np.testing.assert_allclose(sols[0], q, atol=1e-6)  # nearest to the reference first
        for i, s in enumerate(sols):
            np.testing.assert_allclose(kin.flange_pose(s), target, atol=2e-6)
            assert all(np.abs(s - o).max() > 1e-6 for o in sols[:i])


def test_unreachable_target_fails_fast_with_a_reason(kin):
    far = np.eye(4)
    far[:3, 3] = [3.0, 0.0, 0.2]
    r = kin.ik(far, seed=np.zeros(6))
    assert isinstance(r, IkResult)
    assert not r.success and r.q is None
    assert "out of reach" in r.message
    assert r.position_error > 1.0
    axis = np.eye(4)
    axis[:3, 3] = [0.0, 0.0, 0.6]  # wrist centre on the joint-1 axis: impossible with d4 > 0
    r = kin.ik(axis)
    assert not r.success and "out of reach" in r.message


def test_joint_limits_are_respected_and_named_when_they_forbid_a_target():
    model = load_model("zu5")
    q = np.array([0.2, 1.0, -1.2, 0.8, 1.0, 0.3])
    # Every joint boxed ±0.3 rad around q, except joint_3 which may only bend the other way.
    lower, upper = q - 0.3, q + 0.3
    lower[2], upper[2] = 0.1, 3.0
    kin = Kinematics(replace(model, lower=lower, upper=upper))
    r = kin.ik(kin.flange_pose(q), seed=q)
    assert not r.success
    assert "violates joint limits" in r.message and "joint_3" in r.message


def test_damped_least_squares_fallback_solves_without_the_closed_form():
    kin = Kinematics(load_model("zu5"))
    kin._solver = kin._native = None  # as for an arm without a solver of its structure
    q = np.array([0.3, 1.2, -1.0, 0.5, 0.7, 0.2])
    r = kin.ik(kin.flange_pose(q), seed=q + 0.05)
    assert r.success and "damped least squares" in r.message
    np.testing.assert_allclose(r.q, q, atol=1e-6)
    r = kin.ik(kin.flange_pose(q))
    assert r.success
    np.testing.assert_allclose(kin.flange_pose(r.q), kin.flange_pose(q), atol=2e-6)


def test_wrist_singularity_still_solves_and_keeps_the_seed_q6():
    kin = Kinematics(load_model("zu5"))
    q = np.array([0.4, 1.3, -1.1, 0.9, 0.0, 0.7])  # q5 = 0: J4 and J6 coaxial
    r = kin.ik(kin.flange_pose(q), seed=q)
    assert r.success, r.message
    np.testing.assert_allclose(kin.flange_pose(r.q), kin.flange_pose(q), atol=2e-6)
    assert abs(r.q[5] - q[5]) < 1e-3 and abs(r.q[3] - q[3]) < 1e-3


def test_shared_between_threads():
    kin = Kinematics(load_model("zu7"))
    rng = np.random.default_rng(8)
    qs = _random_q(kin, rng, 50)
    targets = [kin.flange_pose(q) for q in qs]
    expected = [kin.ik(T, seed=q).q for T, q in zip(targets, qs)]
    errors = []

    def worker():
        for _ in range(5):
            for T, q, e in zip(targets, qs, expected):
                got = kin.ik(T, seed=q).q
                if not np.array_equal(got, e):
                    errors.append((q, got, e))

    threads = [threading.Thread(target=worker) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors


def test_inputs_are_validated_at_the_door():
    kin = Kinematics(load_model("zu5"))
    with pytest.raises(ValueError):
        kin.flange_pose(np.zeros(5))
    with pytest.raises(ValueError):
        kin.flange_pose([0, 0, np.nan, 0, 0, 0])
    with pytest.raises(ValueError):
        kin.ik(np.eye(3))
    with pytest.raises(ValueError):
        kin.ik(np.eye(4), seed=np.zeros(7))
    with pytest.raises(ValueError):
        kin.tcp_pose(np.zeros(6), tool=rotvec_to_matrix([0, 0, 1]))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, 1.0000001e150, -1e200])
def test_forward_kinematics_refuses_nan_inf_and_values_past_1e150(bad):
    kin = Kinematics(load_model("zu5"))
    q = np.zeros(6)
    q[3] = bad
    with pytest.raises(ValueError, match="6 finite values"):
        kin.flange_pose(q)
    tool = np.eye(4)
    tool[1, 3] = bad
    with pytest.raises(ValueError):
        kin.tcp_pose(np.zeros(6), tool)


def test_forward_kinematics_takes_values_up_to_1e150():
    kin = Kinematics(load_model("zu5"))
    q = np.zeros(6)
    q[3] = 1e150               # the compiled path's bound: still a number to it
    assert np.isfinite(kin.flange_pose(q)).all()
