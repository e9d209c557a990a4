"""Trajectory recording's rules and files, without a twin: a point is kept when the tool has
moved xyz_interval or turned rpy_interval since the last kept one (the first always); names
and configurations are refused naming field, value and limit; a recording's replay program is
the twin's program format (a joint move to the first point, then a linear move through each
later one at the configured speed), loaded as track/<name> and nothing outside the folder; a
replay too long for a program is refused; a backend without recording refuses with -9."""
from __future__ import annotations

import math

import numpy as np
import pytest

from jaka_driver.backend import NoRecording, TrajConfig
from jaka_driver.backend.recording import checked_config, checked_name
from jaka_driver.common.results import CommandRefused
from jaka_driver.common.transforms import rotvec_to_matrix
from jaka_driver.programs import FolderPrograms, parse
from jaka_driver.programs.language import JointMove, LinearMove
from jaka_driver.programs.parser import MAX_BYTES
from jaka_driver.programs.track import KeptPoint, TrackFolder
from jaka_driver.sim.recording import PathSampler

Q = np.zeros(6)


def pose(x_mm=0.0, angle_deg=0.0) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = rotvec_to_matrix([0.0, 0.0, math.radians(angle_deg)])
    T[0, 3] = x_mm / 1000.0
    return T


def test_a_point_is_kept_each_time_the_tool_moved_or_turned_the_interval():
    sampler = PathSampler(TrajConfig.from_request(5.0, 2.0, 25.0, 100.0))
    offered = [pose(0), pose(4.9), pose(5.0), pose(9.9, 1.9), pose(9.9, 4.1), pose(15.0, 4.1)]
    kept = [sampler.offer(0.008 * i, Q, T) for i, T in enumerate(offered)]
    assert kept == [True, False, True, False, True, True]
    assert [p.pose_mm[0] for p in sampler.points] == pytest.approx([0.0, 5.0, 9.9, 15.0])
    assert [p.elapsed for p in sampler.points] == pytest.approx([0.0, 0.016, 0.032, 0.04])


@pytest.mark.parametrize("name, words", [
    ("a/b", "filename is 'a/b', expected a program's name"), ("", "filename is ''"),
    ("..", "filename is '..'"), ("x" * 101, "filename has 101 characters, at most 100"),
    (3, "filename is 3, expected a name"),
])
def test_a_name_must_be_a_programs_name_of_at_most_100_characters(name, words):
    with pytest.raises(CommandRefused) as refused:
        checked_name("filename", name)
    assert refused.value.code == -2 and words in str(refused.value.result().message)
    assert checked_name("filename", "x" * 100) == "x" * 100


@pytest.mark.parametrize("values, words", [
    ((0.0, 2, 25, 100), "xyz_interval is 0 mm, expected at least 0.01 and at most 1000 mm"),
    ((5, 181, 25, 100), "rpy_interval is 181 deg, expected at least 0.01 and at most 180 deg"),
    ((5, 2, 0, 100), "vel is 0 mm/s, expected above 0 and at most 1000 mm/s"),
    ((5, 2, 25, 1e6), "acc is 1e+06 mm/s², expected above 0 and at most 2500 mm/s²"),
])
def test_a_configuration_out_of_range_is_refused_naming_field_value_and_limit(values, words):
    with pytest.raises(CommandRefused) as refused:
        checked_config(TrajConfig.from_request(*values), 1.0, 2.5)
    assert words in refused.value.result().message
    good = TrajConfig.from_request(0.01, 0.01, 1000, 2500)
    assert checked_config(good, 1.0, 2.5) is good


def points(n: int):
    return [KeptPoint(0.1 * i, np.array([400.0 + 5 * i, 100.0, 300.0, 3.14, 0.0, 0.0]),
                      np.full(6, 0.01 * i)) for i in range(n)]


def test_the_replay_is_a_joint_move_to_the_start_then_lines_at_the_configured_speed(tmp_path):
    store = TrackFolder(tmp_path)
    config = TrajConfig.from_request(5.0, 2.0, 40.0, 300.0)
    store.save("demo", points(4), config, "tool 0, user frame 0")
    assert store.names() == ["demo"] and store.exists("demo")
    kept = store.load("demo")
    assert [p.pose_mm[0] for p in kept] == [400.0, 405.0, 410.0, 415.0]
    store.write_program("demo", kept, config)
    program = parse((tmp_path / "track" / "demo.jdp").read_text(), "track/demo")
    kinds = [type(s) for s in program.statements]
    assert kinds == [JointMove, LinearMove, LinearMove, LinearMove]
    text = (tmp_path / "track" / "demo.jdp").read_text()
    assert "linear_move [415.0000, 100.0000, 300.0000, 3.140000, 0.000000, 0.000000] speed 40 " \
           "accel 300" in text


def test_the_program_folder_loads_track_programs_and_nothing_outside_it(tmp_path):
    store = TrackFolder(tmp_path)
    store.write_program("demo", points(2), TrajConfig())
    programs = FolderPrograms(str(tmp_path))
    assert programs.available() == ["track/demo"]
    loaded = programs.load("track/demo.jks")
    assert loaded.ok, loaded.message
    assert programs.status().name == "track/demo"
    for name in ("track/../demo", "track/", "other/demo", "track/a/b"):
        refused = programs.load(name)
        assert refused.code == -2, (name, refused.message)


def test_a_replay_longer_than_a_program_may_be_is_refused(tmp_path):
    many = points(MAX_BYTES // 60)
    with pytest.raises(ValueError, match="record with a larger xyz_interval"):
        TrackFolder(tmp_path).write_program("long", many, TrajConfig())
    assert not (tmp_path / "track" / "long.jdp").exists()


def test_a_backend_without_recording_refuses_every_request_with_minus_9():
    facet = NoRecording("trajectory recording is not available on this backend")
    for result in (facet.set_config(TrajConfig()), facet.config(), facet.start("a"),
                   facet.stop(), facet.sampling(), facet.names(), facet.rename("a", "b"),
                   facet.remove("a"), facet.generate("a")):
        assert result.code == -9 and "not available" in result.message
