"""Teaching by demonstration on the twin, in simulated time through RobotDriver's door
(``driver.recording``): the tool is pushed by a hand under tool drive along base x and then y,
the recording keeps a point every ``xyz_interval`` mm of that path, and the replay program it
generates (``track/<name>``, loaded and played by the program services through the engine's
checks) passes within ``xyz_interval`` + 0.5 mm of every kept point. The same requests keep the
same points. Every refusal names the field, the value and the limit, and changes nothing.
Times are sim time: the machine's load changes nothing."""
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.backend import ProgramState
from jaka_driver.programs.track import TrackFolder
from support.sensor_twin import fresh, twin_with_sensor

XYZ_MM, RPY_DEG, VEL, ACC = 5.0, 2.0, 50.0, 200.0


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("programs")


@pytest.fixture(scope="module")
def driver(folder):
    with twin_with_sensor(programs=str(folder)) as d:
        yield d


@pytest.fixture
def arm(driver):
    """A fresh twin at home, its sensor on and zeroed, recording at the test's thresholds."""
    start = fresh(driver, sensor_on=True, settle=0.2, zero=True)
    arm = next(start)
    assert arm.recording.set_config(XYZ_MM, RPY_DEG, VEL, ACC).ok
    yield arm
    arm.recording.set_sample_mode(False)
    start.close()


def samples_for(driver, seconds=None, until=None, limit=60.0):
    """Every sample for ``seconds`` of sim time, or until ``until()`` (at most ``limit`` s)."""
    samples, last, start = [], driver.state().stamp, driver.clock.now()
    while True:
        driver.clock.sleep(0.08)
        for st in driver.states_since(last):
            samples.append(st)
            last = st.stamp
        elapsed = driver.clock.now() - start
        if (seconds is not None and elapsed >= seconds) or (until is not None and until()) \
                or elapsed > limit:
            return samples


def push_a_corner(arm, name):
    """Record ``name`` while a 20 N hand pushes the tool along base x for 1 s, then along y for
    0.8 s, under tool drive; returns the path's samples."""
    f = arm.force
    for axis in (0, 1, 2):
        assert f.set_tool_drive(axis, 1, 40.0, 0.0).ok
    assert f.enable_tool_drive(True).ok
    assert arm.recording.set_sample_mode(True, name).ok
    assert arm.recording.sample_status().value is True
    assert arm.twin.push_tool([20.0, 0, 0, 0, 0, 0], 1.0).ok
    path = samples_for(arm, 1.0)
    assert arm.twin.push_tool([0, 20.0, 0, 0, 0, 0], 0.8).ok
    path += samples_for(arm, 1.3)
    stopped = arm.recording.set_sample_mode(False)
    assert stopped.ok and arm.recording.sample_status().value is False
    assert f.disable().ok
    samples_for(arm, 0.5)                       # tool drive lets the arm come to rest
    return path


def test_a_path_pushed_under_tool_drive_replays_within_the_interval(arm, folder):
    path = push_a_corner(arm, "corner")
    kept = TrackFolder(Path(folder)).load("corner")
    xyz = np.array([s.tcp_pose[:3, 3] * 1000.0 for s in path])
    length = float(np.sum(np.linalg.norm(np.diff(xyz, axis=0), axis=1)))
    steps = np.linalg.norm(np.diff([p.pose_mm[:3] for p in kept], axis=0), axis=1)
    print(f"pushed path {length:.1f} mm, {len(kept)} kept points, steps {steps.min():.2f}–"
          f"{steps.max():.2f} mm")
    assert length > 40.0
    assert np.all(steps >= XYZ_MM) and np.all(steps < XYZ_MM + 1.0)   # one cycle's travel
    assert len(kept) >= length / (XYZ_MM + 1.0)
    assert arm.recording.names().value == ["corner"]

    generated = arm.recording.generate("corner")
    assert generated.ok and generated.value == "track/corner", generated.message
    assert arm.programs.load("track/corner").ok
    assert arm.programs.play().ok
    replay = samples_for(arm, until=lambda: arm.programs.status().state == ProgramState.IDLE)
    status = arm.programs.status()
    assert status.error == "" and status.name == "track/corner", status
    played = np.array([s.tcp_pose[:3, 3] * 1000.0 for s in replay])
    deviation = [float(np.min(np.linalg.norm(played - p.pose_mm[:3], axis=1))) for p in kept]
    print(f"replay {len(replay) * 0.008:.2f} s of sim time, farthest from a kept point "
          f"{max(deviation):.3f} mm")
    assert max(deviation) <= XYZ_MM + 0.5
    assert np.linalg.norm(played[-1] - kept[-1].pose_mm[:3]) <= 0.5      # it ends at the end


def test_the_same_push_keeps_the_same_points(arm, folder):
    push_a_corner(arm, "first")
    assert arm.twin.reset().ok                  # as the fixture's fresh start
    assert arm.force.sensor_enable(True).ok
    arm.clock.sleep(0.2)
    assert arm.force.zero_sensor().ok
    assert arm.recording.set_config(XYZ_MM, RPY_DEG, VEL, ACC).ok
    push_a_corner(arm, "second")
    store = TrackFolder(Path(folder))
    first, second = store.load("first"), store.load("second")
    assert len(first) == len(second)
    assert all(np.array_equal(a.pose_mm, b.pose_mm) for a, b in zip(first, second))


def test_list_rename_and_remove_act_on_the_recordings_and_their_programs(arm, folder):
    rec = arm.recording
    for name in ("keep", "spare"):
        assert rec.set_sample_mode(True, name).ok and rec.set_sample_mode(False).ok
    assert rec.generate("spare").ok
    assert rec.rename("spare", "renamed").ok
    assert {"keep", "renamed"} <= set(rec.names().value) and "spare" not in rec.names().value
    track = Path(folder) / "track"
    assert (track / "renamed.jdp").is_file() and not (track / "spare.jdp").exists()
    assert arm.programs.load("track/renamed").ok
    assert rec.remove("renamed").ok
    assert "renamed" not in rec.names().value and not (track / "renamed.jdp").exists()


@pytest.mark.parametrize("call, code, words", [
    (lambda r: r.set_sample_mode(True, "a/b"), -2, "filename is 'a/b', expected a program's "
                                                   "name"),
    (lambda r: r.set_sample_mode(True, "x" * 101), -2, "filename has 101 characters, at most "
                                                       "100"),
    (lambda r: r.generate("nowhere"), -2, "fileName is 'nowhere': no recording of that name"),
    (lambda r: r.remove("nowhere"), -2, "fileName is 'nowhere': no recording of that name"),
    (lambda r: r.rename("nowhere", "b"), -2, "src is 'nowhere': no recording"),
    (lambda r: r.rename("keep", "../b"), -2, "dest is '../b'"),
    (lambda r: r.set_config(0.0, 2.0, 50.0, 200.0), -2, "xyz_interval is 0 mm, expected at "
                                                        "least 0.01"),
    (lambda r: r.set_config(5.0, -1.0, 50.0, 200.0), -2, "rpy_interval is -1 deg"),
    (lambda r: r.set_config(5.0, 2.0, 0.0, 200.0), -2, "vel is 0 mm/s, expected above 0"),
    (lambda r: r.set_config(5.0, 2.0, 50.0, 1e9), -2, "acc is 1e+09 mm/s², expected above 0 "
                                                      "and at most"),
    (lambda r: r.set_config(float("nan"), 2.0, 50.0, 200.0), -2, "xyz_interval is nan"),
])
def test_every_refusal_names_the_field_the_value_and_the_limit(arm, call, code, words):
    rec = arm.recording
    assert rec.set_sample_mode(True, "keep").ok and rec.set_sample_mode(False).ok
    before = (rec.names().value, rec.config().value)
    result = call(rec)
    assert result.code == code and words in result.message, result.message
    assert (rec.names().value, rec.config().value) == before       # nothing changed


def test_starting_while_recording_and_touching_the_recording_under_way_are_refused(arm):
    rec = arm.recording
    assert rec.set_sample_mode(True, "busy").ok
    again = rec.set_sample_mode(True, "other")
    assert again.code == -10 and "already recording 'busy'" in again.message
    for result in (rec.generate("busy"), rec.remove("busy"), rec.rename("busy", "b")):
        assert result.code == -10 and "fileName is 'busy': it is being recorded" in \
            result.message.replace("src is", "fileName is"), result.message
    assert rec.sample_status().value is True
    assert rec.set_sample_mode(False).ok
    assert rec.generate("busy").ok
