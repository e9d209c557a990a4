"""The controller's kinematic parameters (``get_dh_param``, modified DH): every model's chain is
held exactly by them, a Zu arm comes out in the form JAKA's SDK reads (alpha row
[0, 90, 0, 0, 90, -90], a2 and a3 at indices 2 and 3, d4 negative, no home offsets, frame 6 the
flange), and a real arm's calibration is told apart from another model."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from jaka_driver.kinematics.controller_dh import (CALIBRATION_TOLERANCE, DHParameters,
                                                  chain_difference, dh_of_model, fit_chain,
                                                  flange_pose)
from jaka_driver.common.models import MODEL_NAMES, load_model

RNG = np.random.default_rng(7)
Q = RNG.uniform(-np.pi, np.pi, (100, 6))


def _urdf_flange(model, q):
    pm = pin.buildModelFromXML(model.urdf_xml)
    data = pm.createData()
    pin.framesForwardKinematics(pm, data, np.asarray(q, float))
    return data.oMf[pm.getFrameId("flange")].homogeneous


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_the_parameters_hold_the_urdf_chain_exactly(name):
    model = load_model(name)
    fit = fit_chain(model)
    for q in Q[:40]:
        ours = fit.base_offset @ flange_pose(fit.dh, q) @ fit.flange_offset
        theirs = _urdf_flange(model, q)
        assert np.abs(ours - theirs).max() < 1e-9, q


@pytest.mark.parametrize("name", [n for n in MODEL_NAMES if n.startswith("zu")])
def test_a_zu_arm_comes_out_in_the_form_jakas_sdk_reads(name):
    fit = fit_chain(load_model(name))
    alpha, a, d, home = fit.dh.to_wire()
    # JAKA writes pi/2 as 1.5708 (0.0002 deg off)
    np.testing.assert_allclose(alpha, [0, 90, 0, 0, 90, -90], atol=1e-3)
    # JAKA's files carry CAD dust: J6 placed up to 0.39 mm off its axis (zu20, zu30)
    assert a[0] == a[1] == 0.0 and abs(a[4]) < 0.5 and abs(a[5]) < 0.5
    assert a[2] > 200 and a[3] > 200
    assert d[0] > 100 and d[1] == d[2] == 0.0 and d[3] < -100 and d[4] > 100 and d[5] > 100
    # JAKA's URDFs carry sub-mm CAD offsets: a few thousandths of a degree at most
    assert np.abs(home).max() < 0.01
    np.testing.assert_allclose(fit.flange_offset, np.eye(4), atol=1e-9)


def test_the_zu5_parameters_are_the_transcripts():
    alpha, a, d, home = dh_of_model(load_model("zu5")).to_wire()
    # within the URDF's CAD dust (J4's origin is 0.012 mm off the plane)
    np.testing.assert_allclose(a, [0, 0, 430, 368.5, 0, 0], atol=0.02)
    np.testing.assert_allclose(d, [120.15, 0, 0, -114, 113.5, 107], atol=0.02)


def test_a_calibrated_arm_is_its_own_kinematics_and_no_other():
    # A Zu 5's parameters as read from a real controller (a third-party project's calibration)
    nominal = dh_of_model(load_model("zu5"))
    calibrated = DHParameters.from_sdk(nominal.alpha, [0, 0, 429.733, 368.162, 0, 0],
                                       [121.1, 0, 0, -114.195, 113.416, 107.119], [0.0] * 6)
    assert 0.0005 < chain_difference(calibrated, load_model("zu5")) < CALIBRATION_TOLERANCE
    # JAKA sells the Zu 5's arm also as C5 and Pro 5 (the same chain) and A5 (d4 1 mm longer):
    # a calibration cannot tell those apart, and need not; every other arm it tells apart
    same_arm = {"zu5", "c5", "pro5", "a5"}
    for other in MODEL_NAMES:
        difference = chain_difference(calibrated, load_model(other))
        assert (difference < CALIBRATION_TOLERANCE) == (other in same_arm), (other, difference)


def test_the_wire_rows_round_trip_and_bad_rows_are_refused():
    dh = dh_of_model(load_model("zu7"))
    alpha, a, d, home = dh.to_wire()
    back = DHParameters.from_sdk(np.radians(alpha), a, d, np.radians(home))
    for name in ("alpha", "a", "d", "joint_homeoff"):
        np.testing.assert_allclose(getattr(back, name), getattr(dh, name), atol=1e-15)
    assert "-0.000" not in dh.describe()
    with pytest.raises(ValueError, match="alpha"):
        DHParameters([0.0] * 5, [0.0] * 6, [0.0] * 6, [0.0] * 6)
    with pytest.raises(ValueError, match="d"):
        DHParameters([0.0] * 6, [0.0] * 6, [np.nan] * 6, [0.0] * 6)
