"""JAKA's SDK's eight trajectory-recording functions (test/support/jaka_sdk_recording.py: the
requests and the strict reading of sdk_wire_formats §11, restated in docs/protocol.md) against
the emulator, whose twin records: each returns 0, the requests are §11's bytes, every reply's
errorCode is a string (an int would abort the SDK); a joint move the SDK sends is recorded, and
the program generate_traj_exe_file writes loads as track/<name> through the program commands
and plays to its end, finishing where the recording did. Refusals (a path in a name, 101
characters, starting while recording, generating what does not exist, a speed of 0) return 2
and change nothing."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from support.emulated_arm import emulator_with_programs, programs_folder, sdk_logged_in
from support.jaka_sdk_model import ABS, RC_FAILED, RC_OK
from support.jaka_sdk_recording import SdkRecording
from support.ros_harness import wait_until

from jaka_driver.programs.track import TrackFolder

#: §11's requests, as JAKA's SDK 2.1.14 wrote them
SET_CONFIG = ('{"acc":100.0,"cmdName":"set_traj_config","rpy_interval":0.20,"vel":25.0,'
              '"xyz_interval":0.10}')
START = '{"cmdName":"set_traj_sample_mode","filename":"rec1","mode":1}'
RENAME = '{"cmdName":"rename_traj_file_name","dest":"rec2","src":"rec1"}'
GENERATE = '{"cmdName":"generate_traj_exe_file","fileName":"rec2"}'
REMOVE = '{"cmdName":"remove_traj_file","fileName":"rec2"}'


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return programs_folder(tmp_path_factory.mktemp("programs"))


@pytest.fixture(scope="module")
def emu(folder):
    with emulator_with_programs(folder) as emulator:
        yield emulator


@pytest.fixture
def sdk(emu):
    with sdk_logged_in(emu) as handle:
        yield handle
        SdkRecording(handle).set_traj_sample_mode(False, "")


def test_the_sdk_sets_and_reads_the_configuration_with_sections_11_bytes(sdk):
    rec = SdkRecording(sdk)
    assert rec.set_traj_config(0.1, 0.2, 25.0, 100.0) == RC_OK
    assert sdk.sent[-1] == SET_CONFIG
    assert rec.get_traj_config() == (RC_OK, pytest.approx((0.1, 0.2, 25.0, 100.0)))
    assert sdk.sent[-1] == '{"cmdName":"get_traj_config"}'


def test_the_sdk_records_a_move_generates_and_plays_its_replay(sdk, folder):
    rec = SdkRecording(sdk)
    assert rec.set_traj_config(20.0, 5.0, 200.0, 2000.0) == RC_OK
    home = sdk.get_robot_status()[1].joint_position
    assert rec.set_traj_sample_mode(True, "rec1") == RC_OK and sdk.sent[-1] == START
    assert rec.get_traj_sample_status() == (RC_OK, 1)
    target = list(home)
    target[0] += 0.15                                       # J1 0.15 rad: ~75 mm of the tool
    assert sdk.joint_move(target, ABS, 1.0, 5.0) == RC_OK
    assert sdk.wait_inpos(5.0)
    assert rec.set_traj_sample_mode(False, "rec1") == RC_OK
    assert rec.get_traj_sample_status() == (RC_OK, 0)
    assert rec.get_exist_traj_file_name() == (RC_OK, ["rec1"])
    assert rec.rename_traj_file_name("rec1", "rec2") == RC_OK and sdk.sent[-1] == RENAME
    assert rec.get_exist_traj_file_name() == (RC_OK, ["rec2"])
    assert rec.generate_traj_exe_file("rec2") == RC_OK and sdk.sent[-1] == GENERATE
    kept = TrackFolder(Path(folder)).load("rec2")
    assert len(kept) >= 3                                   # ~75 mm every 20 mm

    assert sdk.joint_move(home, ABS, 1.0, 5.0) == RC_OK    # away from the recorded path
    assert sdk.wait_inpos(5.0)
    assert sdk.program_load("track/rec2") == RC_OK
    assert sdk.get_loaded_program() == (RC_OK, "track/rec2.jks")
    assert sdk.program_run() == RC_OK
    assert wait_until(lambda: sdk.get_program_state()[1] == 0, 15.0)
    end = np.array(sdk.get_robot_status()[1].cartesiantran_position[:3])
    print(f"{len(kept)} kept points; the replay ends {np.linalg.norm(end - kept[-1].pose_mm[:3]):.3f}"
          " mm from the last")
    assert np.linalg.norm(end - kept[-1].pose_mm[:3]) < 0.5
    assert rec.remove_traj_file("rec2") == RC_OK and sdk.sent[-1] == REMOVE
    assert rec.get_exist_traj_file_name() == (RC_OK, [])


@pytest.mark.parametrize("call, words", [
    (lambda r: r.set_traj_sample_mode(True, "a/b"), "filename is 'a/b'"),
    (lambda r: r.set_traj_sample_mode(True, "x" * 101), "filename has 101 characters, at most "
                                                        "100"),
    (lambda r: r.generate_traj_exe_file("nowhere"), "fileName is 'nowhere': no recording"),
    (lambda r: r.remove_traj_file("nowhere"), "fileName is 'nowhere': no recording"),
    (lambda r: r.rename_traj_file_name("nowhere", "b"), "src is 'nowhere': no recording"),
    (lambda r: r.set_traj_config(5.0, 2.0, 0.0, 100.0), "vel is 0 mm/s, expected above 0"),
])
def test_a_refusal_returns_2_with_a_string_error_code_and_its_reason(sdk, call, words):
    rec = SdkRecording(sdk)
    assert call(rec) == RC_FAILED
    _, reply = sdk.call("get_traj_sample_status")      # the connection still answers
    assert reply["errorCode"] == "0" and reply["sampleStatus"] == 0
    request = json.loads(sdk.sent[-2])
    _, refusal = sdk.call(request.pop("cmdName"), **request)   # again, its reply read
    assert refusal["errorCode"] == "1" and words in refusal["errorMsg"], refusal   # a value


def test_starting_while_recording_is_refused_and_the_first_recording_goes_on(sdk):
    rec = SdkRecording(sdk)
    assert rec.set_traj_sample_mode(True, "first") == RC_OK
    assert rec.set_traj_sample_mode(True, "second") == RC_FAILED
    _, refusal = sdk.call("set_traj_sample_mode", filename="second", mode=1)
    assert refusal["errorCode"] == "2" and "already recording 'first'" in refusal["errorMsg"]
    assert rec.get_traj_sample_status() == (RC_OK, 1)
    assert rec.set_traj_sample_mode(False, "first") == RC_OK
    assert "first" in rec.get_exist_traj_file_name()[1]
    assert "second" not in rec.get_exist_traj_file_name()[1]
