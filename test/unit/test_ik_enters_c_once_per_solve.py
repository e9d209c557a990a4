"""Every IK request crosses into the compiled library at most once, whatever the outcome.

The calls are counted at the ctypes boundary (the library object the wrapper calls through), on
requests where the compiled path succeeds, where it fails and the Python path explains the
failure (target out of reach, joint limits), with a tool and a user frame, without a seed, and
with arrays C cannot read as they are. A failing compiled solve must not be repeated: the
second entry would compute the same answer again.
"""
from dataclasses import replace

import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.common.transforms import pose_to_matrix
from jaka_driver.kinematics import Kinematics

Q = np.array([0.2, 1.0, -1.2, 0.8, 1.0, 0.3])


class CountingLibrary:
    """The loaded library, with every function call through it recorded as (name, return)."""

    def __init__(self, lib):
        self._lib = lib
        self.calls: list[tuple[str, int]] = []

    def __getattr__(self, name):
        function = getattr(self._lib, name)

        def counted(*args):
            result = function(*args)
            self.calls.append((name, result))
            return result
        return counted


def counted(kin: Kinematics) -> CountingLibrary:
    assert kin._native is not None, "devel/lib/libjaka_ik.so missing: run make setup"
    counter = CountingLibrary(kin._native._lib)
    kin._native._lib = counter
    return counter


@pytest.fixture(scope="module")
def kin():
    return Kinematics(load_model("zu5"))


@pytest.fixture
def calls(kin):
    lib = kin._native._lib
    counter = counted(kin)
    yield counter.calls
    kin._native._lib = lib


def test_a_solved_request_enters_c_once(kin, calls):
    r = kin.ik(kin.flange_pose(Q), seed=Q + 0.01)
    assert r.success
    assert len(calls) == 1 and calls[0][1] >= 1      # solved there: >= 1 Newton step


def test_an_unreachable_target_enters_c_once_and_the_python_path_explains(kin, calls):
    far = np.eye(4)
    far[:3, 3] = [3.0, 0.0, 0.2]                      # m, twice the zu5's reach
    r = kin.ik(far, seed=Q)
    assert not r.success and "out of reach" in r.message
    assert calls == [(calls[0][0], 0)]                # one entry, which failed


def test_a_target_forbidden_by_joint_limits_enters_c_once():
    model = load_model("zu5")
    lower, upper = Q - 0.3, Q + 0.3                   # rad, joint_3 may only bend the other way
    lower[2], upper[2] = 0.1, 3.0
    boxed = Kinematics(replace(model, lower=lower, upper=upper))
    counter = counted(boxed)
    r = boxed.ik(boxed.flange_pose(Q), seed=Q)
    assert not r.success and "joint_3" in r.message
    assert len(counter.calls) == 1 and counter.calls[0][1] == 0


def test_random_targets_where_the_seeded_branch_fails_enter_c_once(kin, calls):
    """Seeds 0.2 rad off random configurations: the rare targets the compiled path leaves to
    the Python path (a neighbouring branch, a singular spot) still cross once."""
    rng = np.random.default_rng(1)
    lo, hi = kin.model.lower, kin.model.upper
    failed_in_c = 0
    for _ in range(3000):
        q = rng.uniform(lo, hi)
        seed = np.clip(q + rng.uniform(-0.2, 0.2, 6), lo, hi)
        calls.clear()
        kin.ik(kin.flange_pose(q), seed=seed)
        assert len(calls) == 1, calls
        failed_in_c += calls[0][1] == 0
    assert failed_in_c >= 1     # the set does hold requests the compiled path refused


@pytest.mark.parametrize("request_kind", ["tool and user", "no seed", "read-only arrays",
                                          "Fortran order", "lists"])
def test_every_kind_of_request_enters_c_once(kin, calls, request_kind):
    tool = user = None
    seed = Q + 0.01
    target = kin.flange_pose(Q)
    if request_kind == "tool and user":
        tool = pose_to_matrix([0.01, -0.02, 0.12, 0.1, -0.2, 0.3])
        user = pose_to_matrix([0.4, 0.1, 0.05, 0.0, 0.0, 0.7])
        target = kin.tcp_pose(Q, tool, user)
    elif request_kind == "no seed":
        seed = None
    elif request_kind == "read-only arrays":
        target.setflags(write=False)
        seed.setflags(write=False)
    elif request_kind == "Fortran order":
        target = np.asfortranarray(target)
    else:
        target, seed = target.tolist(), seed.tolist()
    r = kin.ik(target, seed=seed, tool=tool, user=user)
    assert r.success, r.message
    assert len(calls) == 1 and calls[0][1] >= 1
