"""The controller backend's programs, servo filter and circular move on the fake controller, which
answers as the recorded controller did (test/data/command_transcript.txt: no programs
configured): what goes out is what JAKA's SDK writes (sdk_wire_formats §4, §6, §9), and what
the recorded controller answers is read as the SDK reads it — its "idle" state string, its
refusal to load a program it does not have."""
from __future__ import annotations

import json

import numpy as np

from support.fake_controller import backend, fake  # noqa: F401 - fixtures
from support.ros_harness import wait_until

from jaka_driver.backend import ProgramState
from jaka_driver.motion.servo_filters import checked_spec
from jaka_driver.common.models import load_model


def _sent(fake, name: str) -> list:
    return [json.dumps(r, sort_keys=True) for r in fake.received(name)]


def test_the_state_is_read_from_the_controllers_string_in_the_background(fake, backend):
    assert wait_until(lambda: fake.received("get_program_state"), 2.0)
    assert backend.programs.status().state == ProgramState.IDLE
    assert backend.state().program_state == 0


def test_load_sends_the_name_with_the_jks_the_sdk_appends_once(fake, backend):
    refused = backend.programs.load("pick")
    assert refused.code == 2 and "pick.jks does not exist" in refused.message
    assert backend.programs.load("pick.jks").code == 2          # not pick.jks.jks
    assert _sent(fake, "load_program") == [
        '{"cmdName": "load_program", "programName": "pick.jks"}'] * 2
    assert backend.programs.play().code == 2                    # "no program loaded"
    assert backend.programs.loaded().value == ""


def test_a_variable_the_controller_does_not_list_is_refused_before_anything_is_sent(
        fake, backend):
    assert backend.programs.variables().value == []
    refused = backend.programs.set_variable(5, 2.5, "abc")
    assert refused.code == -2 and "id is 5" in refused.message
    assert not fake.received("modify_user_defined_variable")


def test_a_servo_filter_goes_out_as_the_sdk_writes_it(fake, backend):
    spec = checked_spec(load_model("zu5"), 5, {"mmf_buffer": 15, "mmf_kp": 0.03})
    assert backend.set_servo_filter(spec).ok
    assert fake.received("set_servo_move_filter")[-1] == {
        "cmdName": "set_servo_move_filter", "filter_type": 5, "mmf_kp": 0.03, "mmf_max_buf": 15}
    assert "(sent; a controller cannot report it)" in backend.describe()["servo_filter"]


def test_movc_goes_out_with_the_sdks_keys_and_types(fake, backend):
    start = backend.state().tcp_pose
    mid, end = start.copy(), start.copy()
    mid[:3, 3] += [0.04, 0.04, 0.0]
    end[:3, 3] += [0.08, 0.0, 0.0]
    backend.start_circular_move(mid, end, 0.1, 0.5, 1.5, 2)
    sent = fake.received("movc")
    assert len(sent) == 1, "the arc was refused before movc: " + str(backend.state())
    movc = sent[0]
    assert sorted(movc) == ["accel", "circle_cnt", "circle_mode", "cmdName",
                            "executing_line_id", "pos_end", "pos_mid", "relFlag", "speed",
                            "tol"]
    assert isinstance(movc["circle_cnt"], float) and movc["circle_cnt"] == 1.5
    assert isinstance(movc["circle_mode"], int) and movc["circle_mode"] == 2
    assert (movc["speed"], movc["accel"], movc["relFlag"], movc["executing_line_id"]) == \
        (100.0, 500.0, 0, 1)
    assert np.allclose(movc["pos_end"][:3], end[:3, 3] * 1000.0)
