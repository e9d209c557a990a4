"""Trajectory recording through ROS on one node (the zu5 twin, its programs folder a temporary
one): the eight services are there under JAKA's SDK names; with the README's command lines, their
YAML called as written, a joint move made while recording is recorded, generated as
track/<name>, loaded and played by the program services to its end, the last kept point (at
most xyz_interval before the move's end), then listed, renamed and removed; the configuration
reads back in the request's units; refusals come back with ret -2 / -10 naming the field and
value, and change nothing."""
import shlex
from pathlib import Path

import numpy as np
import pytest
import rosservice
import yaml
from jaka_msgs.srv import GetFK, Move

from jaka_driver.programs.track import TrackFolder
from jaka_driver_msgs.msg import ProgramState
from jaka_driver_msgs.srv import (GetTrajConfig, GetTrajFiles, GetTrajSampleStatus,
                                  LoadProgram, ProgramCommand, RenameTrajFile, SetTrajConfig,
                                  SetTrajSampleMode, TrajFile)
from support.ros_harness import START, Recorder, go_home, position, start_driver, wait_until

pytestmark = pytest.mark.ros

RECORDING_SERVICES = {"set_traj_config", "get_traj_config", "set_traj_sample_mode",
                      "get_traj_sample_status", "get_exist_traj_file_name",
                      "rename_traj_file_name", "remove_traj_file", "generate_traj_exe_file"}


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("programs")


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node, folder):
    """conftest's node on the zu5 twin, with a programs folder of its own (conftest's ``call``
    and ``joints`` are on it)."""
    return start_driver(request, backend="sim", model="zu5", programs=str(folder))


@pytest.fixture(scope="module")
def program_state(sim_driver):
    recorder = Recorder(sim_driver.name("program/state"), ProgramState)
    yield recorder
    recorder.close()


README = Path(__file__).resolve().parents[2] / "README.md"
#: the types of the services the README's recording lines call
TYPES = {"set_traj_config": SetTrajConfig, "set_traj_sample_mode": SetTrajSampleMode,
         "generate_traj_exe_file": TrajFile,
         "program/load": LoadProgram, "program/play": ProgramCommand}


def readme(call, start: str) -> list:
    """The README's one line starting ``rosservice call /jaka_driver/<start>``: each of its
    ``rosservice call SERVICE "YAML"`` commands called with the YAML's fields as written (as
    rosservice reads them; the CLI's own start-up, ~0.7 s a call, is left out), the replies."""
    prefix = f"rosservice call /jaka_driver/{start}"
    lines = [line for line in README.read_text().splitlines() if line.startswith(prefix)]
    assert len(lines) == 1, f"README.md has {len(lines)} lines starting {prefix!r}"
    replies = []
    for command in lines[0].split("&&"):
        words = shlex.split(command.split("#", 1)[0])
        assert words[:2] == ["rosservice", "call"] and len(words) == 4, command
        service = words[2][len("/jaka_driver/"):]
        fields = yaml.safe_load(words[3]) or {}
        replies.append(call(service, TYPES[service], **fields))
    return replies


def test_the_readmes_recording_replays_as_track_program_to_its_end(call, program_state,
                                                                   joints, folder):
    served = {name.split("/jaka_driver/", 1)[1] for name in rosservice.get_service_list()
              if name.startswith("/jaka_driver/")}
    assert RECORDING_SERVICES <= served, RECORDING_SERVICES - served
    go_home(call)
    assert [r.ret for r in readme(call, "set_traj_config")] == [1, 1]     # and start
    config = call("get_traj_config", GetTrajConfig)
    assert (config.xyz_interval, config.rpy_interval, config.vel, config.acc) == \
        pytest.approx((20.0, 5.0, 200.0, 2000.0))
    assert call("get_traj_sample_status", GetTrajSampleStatus).sampling
    target = list(START)
    target[0] += 0.15                                       # ~75 mm of the tool
    assert call("joint_move", Move, pose=target, mvvelo=1.0, mvacc=5.0).ret == 1
    played = readme(call, 'set_traj_sample_mode "{start: false')   # stop, generate, play
    assert [r.ret for r in played] == [1, 1, 1, 1], played
    assert not call("get_traj_sample_status", GetTrajSampleStatus).sampling
    end = np.array(call("get_fk", GetFK, joint=target).cartesian_pose[:3])
    done = wait_until(lambda: (m := program_state.latest()) and m.name == "track/taught"
                      and m.state == 0 and m, 15.0)
    assert done and done.error == "", program_state.latest()
    here = np.array(call("get_fk", GetFK, joint=list(position(joints))).cartesian_pose[:3])
    last = TrackFolder(folder).load("taught")[-1].pose_mm[:3]
    assert np.linalg.norm(here - last) < 0.5                # the last kept point,
    assert np.linalg.norm(here - end) < 20.0 + 0.5          # the move's end within the interval
    assert call("get_exist_traj_file_name", GetTrajFiles).names == ["taught"]
    assert call("rename_traj_file_name", RenameTrajFile, src="taught", dest="kept").ret == 1
    assert call("get_exist_traj_file_name", GetTrajFiles).names == ["kept"]
    assert call("remove_traj_file", TrajFile, name="kept").ret == 1
    assert call("get_exist_traj_file_name", GetTrajFiles).names == []


def test_refusals_through_ros_name_field_and_value_and_change_nothing(call):
    before = call("get_exist_traj_file_name", GetTrajFiles).names
    for name, srv, fields, ret, words in (
            ("set_traj_sample_mode", SetTrajSampleMode, dict(start=True, filename="a/b"), -2,
             "filename is 'a/b'"),
            ("generate_traj_exe_file", TrajFile, dict(name="nowhere"), -2,
             "fileName is 'nowhere': no recording"),
            ("set_traj_config", SetTrajConfig, dict(xyz_interval=1.0, rpy_interval=1.0,
                                                    vel=0.0, acc=100.0), -2, "vel is 0 mm/s")):
        reply = call(name, srv, **fields)
        assert reply.ret == ret and words in reply.message, (name, reply.message)
    assert call("set_traj_sample_mode", SetTrajSampleMode, start=True, filename="one").ret == 1
    again = call("set_traj_sample_mode", SetTrajSampleMode, start=True, filename="two")
    assert again.ret == -10 and "already recording 'one'" in again.message
    assert call("set_traj_sample_mode", SetTrajSampleMode, start=False, filename="").ret == 1
    assert call("get_exist_traj_file_name", GetTrajFiles).names == sorted(before + ["one"])
