"""The issue's checks on the controller backend, through the emulator (a RobotDriver on a
ControllerBackend, JAKA's commands on 127.0.0.1, the twin behind them): a three-move program
plays to idle at its end pose; paused inside a move the arm rests within the move's stop
distance and motion_state reads 1 (paused) from the next sample on; resumed it ends at the same
pose; stop ends the program with the motion queue empty; a user variable set through the
driver is read back and counted by the program; circular_move goes out as movc, runs the
twin's arc and ends on its end pose, and three points on one line are refused before anything
is sent; a servo filter goes out as set_servo_move_filter and shows in describe().

Times here are wall-clock (the emulator's twin runs on it): where a check needs one, it allows
for the measurement's own resolution — the status period and the time the pause took to go
out and come back, measured in the same run."""
from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from support.emulated_arm import driver_on_emulator, programs_folder
from support.ros_harness import wait_until

from jaka_driver.backend import ProgramState
from jaka_driver.backend.robot_state import MotionState
from jaka_driver.common.transforms import matrix_to_pose_mm, pose_mm_to_matrix
from jaka_driver.motion.circular_path import arc_through

END_MM = np.array([642.0, 114.0, 393.0])     # where three_moves.jdp's half circle ends
LINE_OF_THE_LINE = 6                         # its linear move: 50 mm down at 100 mm/s
LINE_SPEED, LINE_ACCEL = 100.0, 500.0        # mm/s, mm/s² of that move


@pytest.fixture(scope="module")
def arm(tmp_path_factory):
    with driver_on_emulator(programs=programs_folder(tmp_path_factory.mktemp("programs"))) \
            as (emu, driver):
        yield emu, driver


@pytest.fixture
def driver(arm):
    emu, driver = arm
    yield driver
    driver.programs.stop()
    wait_until(lambda: not driver.state().moving, 5.0)


def _tcp_mm(st) -> np.ndarray:
    return st.tcp_pose[:3, 3] * 1000.0


def _idle(driver, timeout: float) -> bool:
    return wait_until(lambda: driver.programs.status().state == ProgramState.IDLE
                      and not driver.state().moving, timeout)


def _home(driver) -> None:
    assert driver.joint_move(driver.model.home, 1.0, 2.0).ok


def test_a_three_move_program_plays_to_idle_at_its_end_pose(driver):
    _home(driver)
    assert driver.programs.load("three_moves").ok
    assert driver.programs.loaded().value == "three_moves"
    assert driver.programs.play().ok
    st = driver.state()
    assert st.program_state == ProgramState.RUNNING and st.motion_state == MotionState.RUNNING
    assert _idle(driver, 20.0)
    status = driver.programs.status()
    assert (status.line, status.error) == (0, "")
    assert np.linalg.norm(_tcp_mm(driver.state()) - END_MM) < 0.5
    assert driver.state().motion_state == MotionState.STOP


def test_paused_inside_a_move_the_arm_rests_on_its_path_and_resumes_to_the_same_end(driver):
    _home(driver)
    assert driver.programs.load("three_moves").ok and driver.programs.play().ok
    # inside the line, at its speed: 100 mm/s
    assert wait_until(lambda: driver.programs.status().line == LINE_OF_THE_LINE
                      and np.linalg.norm(driver.state().joint_velocity) > 0.05, 10.0)
    time.sleep(0.2)
    before = driver.state()
    sent = time.time()
    assert driver.programs.pause().ok
    took = time.time() - before.stamp                  # the sample's age + the round trip
    paused = driver.state()
    assert paused.motion_state == MotionState.PAUSE          # the next sample says paused
    assert driver.programs.status().state == ProgramState.PAUSED
    assert wait_until(lambda: _still(driver), 3.0)
    rest = _tcp_mm(driver.state())
    stop_distance = LINE_SPEED ** 2 / (2 * LINE_ACCEL)          # 10 mm at the move's own
    moved = np.linalg.norm(rest - _tcp_mm(before))
    # Wall clock: the controller backend's samples are stamped in wall time (time.time, µs):
    # the allowance is the distance the line covers in the measured age + round trip, so a
    # loaded machine widens the bound by exactly what it delayed.
    assert moved <= stop_distance + LINE_SPEED * took, (moved, took, sent - before.stamp)
    assert abs(rest[0] - 482.0) < 0.5 and abs(rest[1] - 114.0) < 0.5   # on the line
    assert driver.programs.status().line == LINE_OF_THE_LINE
    assert driver.programs.resume().ok
    assert driver.state().motion_state == MotionState.RUNNING
    assert _idle(driver, 20.0)
    assert np.linalg.norm(_tcp_mm(driver.state()) - END_MM) < 0.5


def _still(driver) -> bool:
    """The TCP moves less than 0.05 mm over 0.2 s."""
    before = _tcp_mm(driver.state())
    time.sleep(0.2)
    return np.linalg.norm(_tcp_mm(driver.state()) - before) < 0.05


def test_stop_ends_the_program_and_empties_the_queue(arm, driver):
    emu, _ = arm
    _home(driver)
    assert driver.programs.load("three_moves").ok and driver.programs.play().ok
    assert wait_until(lambda: driver.programs.status().line >= LINE_OF_THE_LINE, 10.0)
    assert driver.programs.stop().ok
    assert driver.programs.status().state == ProgramState.IDLE
    assert emu.controller.queued == 0 and not emu.controller.moving
    assert wait_until(lambda: _still(driver), 3.0)
    assert driver.programs.status().state == ProgramState.IDLE      # nothing more of it runs
    assert np.linalg.norm(_tcp_mm(driver.state()) - END_MM) > 10.0


def test_a_variable_set_through_the_driver_is_read_back_and_counted_by_the_program(driver):
    assert driver.programs.load("count_cycles").ok
    assert driver.programs.set_variable(1, 3.0).ok                 # the name is kept
    listed = [(v.id, v.value, v.alias) for v in driver.programs.variables().value]
    assert listed == [(1, 3.0, "cycles"), (2, 0.0, "done")]
    assert driver.programs.play().ok
    assert _idle(driver, 5.0)
    assert [(v.id, v.value) for v in driver.programs.variables().value] == [(1, 3.0), (2, 3.0)]
    refused = driver.programs.set_variable(9, 1.0)
    assert refused.code == -2 and "id is 9" in refused.message


def test_a_circular_move_goes_out_as_movc_and_runs_the_twins_arc(arm, driver):
    emu, _ = arm
    _home(driver)
    start = driver.state().tcp_pose
    mid, end = start.copy(), start.copy()
    mid[:3, 3] += [0.04, 0.04, 0.0]
    end[:3, 3] += [0.08, 0.0, 0.0]
    samples = []
    recorder = _Recorder(driver, samples)
    result = driver.circular_move(matrix_to_pose_mm(mid), matrix_to_pose_mm(end), 100.0, 500.0)
    recorder.stop()
    assert result.ok, result.message
    assert emu.handlers.counts["movc"] == 1
    assert np.linalg.norm(_tcp_mm(driver.state()) - end[:3, 3] * 1000.0) < 0.5
    arc = arc_through(start[:3, 3], mid[:3, 3], end[:3, 3])
    off = arc.distance_from(np.array([st.tcp_pose[:3, 3] for st in samples])) * 1000.0
    assert len(samples) > 50 and off.max() < 0.1, off.max()        # mm, every status packet
    line_mid = (end[:3, 3] + start[:3, 3]) / 2
    collinear = end.copy()
    collinear[:3, 3] = line_mid
    refused = driver.circular_move(matrix_to_pose_mm(collinear),
                                   matrix_to_pose_mm(pose_mm_to_matrix(
                                       matrix_to_pose_mm(start))), 100.0, 500.0)
    assert refused.code == -2 and "collinear" in refused.message
    assert emu.handlers.counts["movc"] == 1                        # nothing was sent


def test_a_servo_filter_goes_out_as_set_servo_move_filter(arm, driver):
    emu, _ = arm
    assert driver.set_servo_filter(5, mmf_buffer=15, mmf_kp=0.03).ok
    assert emu.controller.servo_filter == (5, {"mmf_max_buf": 15, "mmf_kp": 0.03})
    assert "speed foresight (buffer 15, kp 0.03) (sent" in driver.describe()["servo_filter"]
    assert driver.set_servo_filter(0).ok
    assert emu.controller.servo_filter == (0, {})


class _Recorder:
    """Every sample (status packet) of ``driver`` into ``samples`` until :meth:`stop`."""

    def __init__(self, driver, samples: list):
        self._driver, self._samples = driver, samples
        self._quit = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        last = self._driver.state().stamp
        while not self._quit.is_set():
            if self._driver.wait_for_sample(last, 0.1):
                st = self._driver.state()
                last = st.stamp
                self._samples.append(st)

    def stop(self) -> None:
        self._quit.set()
        self._thread.join(1.0)
