"""A model rebuilt on a set of the controller's kinematic parameters (a calibration, or another
arm's) is exactly that chain for every model: its FK is the parameters' own (with the model's
base and flange offsets), the parameters read back from it are the ones put in, and its IK —
closed form or the structure's solver, polished on the exact chain — lands on the target to
a micrometre, through the compiled path. A calibration file or seed gives the emulator's arm."""
from __future__ import annotations

import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.emulator.calibration import arm_model, read_parameters
from jaka_driver.kinematics import Kinematics
from jaka_driver.kinematics.calibrated_chain import perturbed, with_dh
from jaka_driver.kinematics.controller_dh import (CALIBRATION_TOLERANCE, chain_difference,
                                                  dh_of_model, fit_chain, flange_pose)

RNG = np.random.default_rng(11)


def _wrapped(a, b):
    return np.abs((np.asarray(a) - np.asarray(b) + np.pi) % (2 * np.pi) - np.pi)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_the_rebuilt_model_is_the_parameters_chain(name):
    model = load_model(name)
    nominal = fit_chain(model)
    dh = perturbed(nominal.dh, 5)
    # a calibration: sub-millimetre, and not nothing
    assert 0.2e-3 < chain_difference(dh, nominal.dh) < CALIBRATION_TOLERANCE
    rebuilt = with_dh(model, dh)
    kin = Kinematics(rebuilt)
    for q in RNG.uniform(-np.pi, np.pi, (30, 6)):
        expected = nominal.base_offset @ flange_pose(dh, q) @ nominal.flange_offset
        assert np.abs(kin.flange_pose(q) - expected).max() < 1e-12
    back = fit_chain(rebuilt)
    assert chain_difference(back.dh, dh) < 1e-9     # the parameters read back are the chain
    if model.structure == "zu":     # and, in the form a Zu arm's controller states, the same
        for field in ("a", "d"):    # numbers (other structures may flip a normal's sense)
            np.testing.assert_allclose(getattr(back.dh, field), getattr(dh, field), atol=1e-6)
        for field in ("alpha", "joint_homeoff"):
            assert _wrapped(getattr(back.dh, field), getattr(dh, field)).max() < 1e-6
    # what the convention cannot hold stays the model's; so do limits and masses
    np.testing.assert_allclose(back.base_offset, nominal.base_offset, atol=1e-9)
    np.testing.assert_allclose(back.flange_offset, nominal.flange_offset, atol=1e-9)
    assert rebuilt.name == model.name and rebuilt.arm_mass_kg == model.arm_mass_kg
    np.testing.assert_array_equal(rebuilt.upper, model.upper)


@pytest.mark.parametrize("name", ["zu5", "zu20", "s7", "a12", "minicobo"])
def test_ik_on_a_calibrated_chain_lands_exactly_through_the_compiled_path(name):
    model = load_model(name)
    kin = Kinematics(with_dh(model, perturbed(dh_of_model(model), 9)))
    assert kin._native is not None, "the compiled IK library is not built (make setup)"
    lo, hi = np.maximum(model.lower, -3.0), np.minimum(model.upper, 3.0)
    for q in RNG.uniform(lo, hi, (60, 6)):
        target = kin.flange_pose(q)
        result = kin.ik(target, seed=q + RNG.uniform(-0.05, 0.05, 6))
        assert result.success, result.message
        assert np.abs(kin.flange_pose(result.q)[:3, 3] - target[:3, 3]).max() < 1e-6


def test_the_emulators_arm_is_the_options_chain(tmp_path):
    zu5 = load_model("zu5")
    assert arm_model(zu5) is zu5
    zu7_chain = arm_model(zu5, dh_from="zu7")
    assert chain_difference(dh_of_model(zu7_chain), load_model("zu7")) < 1e-6
    assert zu7_chain.name == "zu5"      # the zu5's limits and masses on the zu7's chain
    seeded = dh_of_model(arm_model(zu5, calibration="3"))
    assert chain_difference(seeded, perturbed(dh_of_model(zu5), 3)) < 1e-9
    # a controller's reply saved as it came
    path = tmp_path / "arm.json"
    path.write_text('{"dh_param": [[0, 90, 0, 0, 90, -90], [0, 0, 429.733, 368.162, 0, 0], '
                    '[121.1, 0, 0, -114.195, 113.416, 107.119], [0, 0, 0, 0, 0, 0]]}')
    from_file = dh_of_model(arm_model(zu5, calibration=str(path)))
    np.testing.assert_allclose(from_file.a * 1000, [0, 0, 429.733, 368.162, 0, 0], atol=1e-6)
    np.testing.assert_allclose(from_file.d * 1000, [121.1, 0, 0, -114.195, 113.416, 107.119],
                               atol=1e-6)
    path.write_text("dh_param: [[0, 90, 0, 0, 90, -90], [0, 0, 430, 368.5, 0, 0]]")
    with pytest.raises(ValueError, match="4 rows of 6"):
        read_parameters(path)
    with pytest.raises(ValueError, match="nowhere"):
        arm_model(zu5, calibration=str(tmp_path / "nowhere.yaml"))
