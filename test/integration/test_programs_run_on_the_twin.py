"""Programs on the twin, each step through RobotDriver (the executor the driver binds), in
simulated time: the three-move example plays to idle at its end pose with motion_state 3 while
it runs; paused inside its arc the arm comes to rest on the arc within the move's stop distance
with motion_state 1, and resumed it ends at the same pose; stop ends it where it stands; a
variable set from outside is read back and seen by the program; a failing step stops the program
with its line and the driver's refusal; other motion requests are refused while it runs."""
from pathlib import Path

import numpy as np
import pytest

from support.ros_harness import wait_until
from support.twin_samples import collected_twin

from jaka_driver.backend import MotionState, ProgramState
from jaka_driver.common.models import load_model, repo_root
from jaka_driver.common.results import Code
from jaka_driver.common.transforms import matrix_to_pose_mm
from jaka_driver.driver import RobotDriver
from jaka_driver.motion.circular_path import arc_through
from jaka_driver.programs import FolderPrograms
from jaka_driver.sim import SimBackend

MODEL = load_model("zu5")
PROGRAMS = repo_root() / "config" / "programs"
ARC_START, ARC_MID, ARC_END = (np.array(p) for p in ([482, 114, 393], [562, 194, 393],
                                                      [642, 114, 393]))    # three_moves.jdp


@pytest.fixture(scope="module")
def twin():
    yield from collected_twin(MODEL, programs=FolderPrograms(str(PROGRAMS)))


@pytest.fixture
def fresh(twin):
    assert twin.twin.reset().ok
    return twin


def idle(twin, timeout=30.0):
    return wait_until(lambda: twin.programs.status().state == ProgramState.IDLE, timeout)


def tcp_mm(twin):
    return matrix_to_pose_mm(twin.state().tcp_pose)[:3]


def test_three_moves_play_to_idle_at_the_end_pose(fresh):
    assert fresh.programs.load("three_moves.jks").ok        # JAKA's SDK's name
    assert fresh.programs.loaded().value == "three_moves"
    t0 = fresh.state().stamp
    assert fresh.programs.play().ok
    assert idle(fresh)
    assert fresh.programs.status().error == ""
    np.testing.assert_allclose(tcp_mm(fresh), ARC_END, atol=0.05)
    during = fresh.samples.since(t0, fresh.state().stamp)
    states = {st.motion_state for st in during}
    assert MotionState.RUNNING in states and MotionState.PAUSE not in states
    assert ProgramState.RUNNING in {st.program_state for st in during}
    assert fresh.state().motion_state == MotionState.STOP


def test_paused_inside_the_arc_the_arm_rests_on_it_and_resumes_to_the_same_end(fresh):
    clock = fresh.clock
    circle = arc_through(ARC_START / 1000, ARC_MID / 1000, ARC_END / 1000)
    assert fresh.programs.load("three_moves").ok
    with clock.hold():
        assert fresh.programs.play().ok
        # the line (~0.7 s) then 1.0 s into the arc (2.7 s)
        while fresh.programs.status().line != 7:
            clock.sleep(0.05)
        clock.sleep(1.0)
        before = fresh.state()
        assert fresh.programs.pause().ok
        clock.sleep(1.0)
        resting = fresh.state()
        assert fresh.programs.status().state == ProgramState.PAUSED
        assert resting.motion_state == MotionState.PAUSE
        assert np.max(np.abs(resting.joint_velocity)) < 1e-3
        assert circle.distance_from(resting.tcp_pose[:3, 3]) * 1000 < 0.1
        # within the stop distance: no farther than the arm's speed over the slowing down
        travelled = np.linalg.norm(resting.tcp_pose[:3, 3] - before.tcp_pose[:3, 3]) * 1000
        assert 0.0 < travelled < 100.0 * 0.5                  # 100 mm/s, < 0.5 s to rest
        assert fresh.joint_move(MODEL.home, 1.0, 2.0).code == Code.BUSY   # the program's
        assert fresh.programs.resume().ok
    assert idle(fresh)
    assert fresh.programs.status().error == ""
    np.testing.assert_allclose(tcp_mm(fresh), ARC_END, atol=0.05)


def test_stop_ends_the_program_where_the_arm_stands(fresh):
    clock = fresh.clock
    assert fresh.programs.load("three_moves").ok
    with clock.hold():
        assert fresh.programs.play().ok
        while fresh.programs.status().line != 7:
            clock.sleep(0.05)
        clock.sleep(0.5)
        assert fresh.programs.stop().ok
        clock.sleep(0.5)
    assert idle(fresh, 5.0)
    status = fresh.programs.status()
    assert (status.state, status.line, status.error) == (ProgramState.IDLE, 0, "")
    st = fresh.state()
    assert np.max(np.abs(st.joint_velocity)) < 1e-3
    assert np.linalg.norm(tcp_mm(fresh) - ARC_END) > 50.0        # it did not finish
    assert fresh.joint_move(MODEL.home, 1.0, 2.0).ok              # the arm is free again


def test_a_variable_set_from_outside_is_read_back_and_seen_by_the_program(fresh):
    assert fresh.programs.load("pick_cycle").ok
    listed = {v.alias: v for v in fresh.programs.variables().value}
    assert (listed["cycles"].id, listed["cycles"].value) == (1, 2.0)
    assert fresh.programs.set_variable(1, 1, "").ok                 # one cycle only
    assert fresh.programs.set_variable(3, 0, "start").ok            # hold the start
    assert [v.value for v in fresh.programs.variables().value] == [1.0, 0.0, 0.0]
    assert fresh.programs.variables().value[2].alias == "start"
    assert fresh.programs.set_variable(9, 1, "").code == Code.INVALID_PARAMETER
    assert fresh.programs.play().ok
    assert wait_until(lambda: fresh.programs.status().line == 9, 5.0)
    assert fresh.state().motion_state == MotionState.RUNNING       # waiting, running
    assert fresh.programs.set_variable(3, 1, "").ok                 # go
    assert idle(fresh)
    assert fresh.programs.status().error == ""
    assert {v.alias: v.value for v in fresh.programs.variables().value}["done"] == 1.0
    assert fresh.get_io("digital", 1, 0, 0).value == 0.0          # released at the end


def test_a_failing_step_stops_the_program_with_its_line_and_the_refusal(tmp_path):
    (tmp_path / "bad.jdp").write_text("# out of reach on line 3\n\n"
                                      "linear_move [3000, 0, 400, 3.1416, 0, 0] speed 100\n"
                                      "wait 1\n")
    (tmp_path / "broken.jdp").write_text("wait 1\nlinear_move [1, 2] speed 100\n")
    driver = RobotDriver(SimBackend(MODEL, sim_time=True, real_time_factor=0,
                                    programs=FolderPrograms(str(tmp_path))))
    driver.start()
    try:
        assert driver.programs.load("bad").ok
        assert driver.programs.play().ok
        assert idle(driver)
        error = driver.programs.status().error
        assert error.startswith("line 3: linear_move refused (-4): ")
        refused = driver.programs.load("broken")
        assert refused.code == Code.INVALID_PARAMETER
        assert "line 2, column 18: the pose (mm, rotation vector rad) has 2 values" in \
            refused.message
        missing = driver.programs.load("nothing")
        assert "no nothing.jdp" in missing.message and "bad, broken" in missing.message
        assert driver.programs.load("../etc/passwd").code == Code.INVALID_PARAMETER
        too_long = driver.programs.load("x" * 300)      # the file system's limit: refused first
        assert too_long.code == Code.INVALID_PARAMETER and "at most 200" in too_long.message
    finally:
        driver.shutdown()
