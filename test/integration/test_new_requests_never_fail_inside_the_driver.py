"""Random requests to circular_move, set_servo_filter and the program methods, on the twin in
simulated time (hypothesis: NaN, ±inf, huge and tiny numbers, wrong lengths, any text): every
answer is a code of docs/interface.md's table — never -3 "failed inside the driver" — and a
refused request leaves the arm where it was."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from support.twin_samples import collected_twin

from jaka_driver.common.models import load_model, repo_root
from jaka_driver.programs import FolderPrograms

MODEL = load_model("zu5")
CODES = {1, -2, -4, -9, -10, -12}
ODD = st.sampled_from([math.nan, math.inf, -math.inf, 3.4e38, -3.4e38, 5e-324, 0.0, -1.0])
NUMBER = st.one_of(ODD, st.floats(-1e4, 1e4, allow_nan=False))
POSE = st.one_of(st.lists(NUMBER, min_size=0, max_size=8),
                 st.lists(st.floats(-800, 800), min_size=6, max_size=6))
FUZZ = settings(max_examples=150, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])


@pytest.fixture(scope="module")
def twin():
    yield from collected_twin(MODEL,
                              programs=FolderPrograms(str(repo_root() / "config" / "programs")))


def answered(result, twin, before):
    assert result.code in CODES, result
    assert "inside the driver" not in result.message, result.message
    if result.code < 0 and result.code != -12:
        np.testing.assert_allclose(twin.state().joint_position, before, atol=1e-6)


@FUZZ
@given(mid=POSE, end=POSE, v=NUMBER, a=NUMBER, turns=NUMBER,
       mode=st.integers(-2**31, 2**31 - 1), coord=st.integers(-3, 3))
def test_circular_move(twin, mid, end, v, a, turns, mode, coord):
    before = twin.state().joint_position.copy()
    answered(twin.circular_move(mid, end, v, a, turns, mode, coord), twin, before)


@FUZZ
@given(kind=st.integers(0, 255), values=st.lists(NUMBER, min_size=10, max_size=10),
       buffer=st.one_of(st.integers(-2**31, 2**31 - 1), ODD))
def test_set_servo_filter(twin, kind, values, buffer):
    before = twin.state().joint_position.copy()
    names = ("lpf_cutoff_hz", "nlf_max_vr", "nlf_max_ar", "nlf_max_jr", "nlf_max_vp",
             "nlf_max_ap", "nlf_max_jp", "mmf_kp", "mmf_kv", "mmf_ka")
    result = twin.set_servo_filter(kind, mmf_buffer=buffer, **dict(zip(names, values)))
    answered(result, twin, before)


@FUZZ
@given(name=st.one_of(st.text(max_size=300), st.sampled_from(
    ["three_moves", "pick_cycle.jks", "../x", "/etc/passwd", ".", "..", "a\x00b", ""])),
       var_id=st.integers(-2**31, 2**31 - 1), value=NUMBER, alias=st.text(max_size=200),
       action=st.sampled_from(["load", "pause", "resume", "stop", "loaded", "variables",
                               "set"]))
def test_program_requests(twin, name, var_id, value, alias, action):
    before = twin.state().joint_position.copy()
    call = {"load": lambda: twin.programs.load(name), "pause": twin.programs.pause,
            "resume": twin.programs.resume, "stop": twin.programs.stop,
            "loaded": twin.programs.loaded, "variables": twin.programs.variables,
            "set": lambda: twin.programs.set_variable(var_id, value, alias)}[action]
    answered(call(), twin, before)
