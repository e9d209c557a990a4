"""One law per quantity: RobotDriver plans a move's duration once (the synchronised joint
profile from where the arm stands, stretched to ``mvtime``; the straight line's time law) and
hands that number to the backend, which plays it or turns it into a wire speed; a backend never
estimates or refuses it again. In-process, on a fake backend that records what it was asked."""
from __future__ import annotations

import threading

import numpy as np
import pytest

from fake_backend import START, FakeBackend
from jaka_driver.common.results import Result
from jaka_driver.common.transforms import pose_mm_to_matrix
from jaka_driver.driver import RobotDriver
from jaka_driver.motion.linear_path import line_duration
from jaka_driver.motion.profiles import SyncJointProfile, joint_move_profile
from support.ros_harness import wait_until

TARGET = START + np.array([0.3, -0.2, 0.1, 0, 0, 0.4])


def _asked(call) -> tuple:
    """Start ``call(driver)`` on a fake backend, finish its move, return the backend call."""
    backend = FakeBackend()
    driver = RobotDriver(backend)
    thread = threading.Thread(target=lambda: call(driver), daemon=True)
    thread.start()
    assert wait_until(lambda: backend.move is not None, 2.0)
    backend.finish_move(Result.success("in position"))
    thread.join(2.0)
    return backend.calls[-1]


def test_a_joint_move_goes_with_the_duration_of_its_profile():
    _, q, speed, accel, duration = _asked(lambda d: d.joint_move(TARGET.tolist(), 1.0, 2.0))
    model = FakeBackend().model
    fastest = SyncJointProfile(START, TARGET, np.minimum(1.0, model.max_velocity),
                               np.minimum(2.0, model.max_acceleration))
    assert duration == pytest.approx(fastest.duration, rel=1e-12)
    assert (speed, accel) == (1.0, 2.0) and np.allclose(q, TARGET)


def test_an_mvtime_is_the_planned_duration():
    *_, duration = _asked(lambda d: d.joint_move(TARGET.tolist(), 1.0, 2.0, mvtime=4.5))
    assert duration == 4.5


def test_a_linear_move_goes_with_the_duration_of_its_line():
    call = _asked(lambda d: d.linear_move([0, 0, 80.0, 0, 0, 0.2], 50.0, 200.0, coord_mode=2))
    _, target, speed, accel, _, duration = call
    here = FakeBackend().state().tcp_pose
    assert np.allclose(target, here @ pose_mm_to_matrix([0, 0, 80.0, 0, 0, 0.2]))
    assert duration == pytest.approx(line_duration(here, target, 0.05, 0.2), rel=1e-12)


def test_a_backend_a_tracking_error_away_plays_the_plan_or_its_fastest():
    """The backend's start differs from the driver's by the drives' tracking error: a plan a
    hair shorter than that start needs is its fastest, not a refusal; a longer one is kept."""
    fastest = SyncJointProfile(START, TARGET, 1.0, 2.0)
    nudged = START + 1e-5
    assert joint_move_profile(nudged, TARGET, 1.0, 2.0, fastest.duration * (1 - 1e-9)) \
        .duration == pytest.approx(fastest.duration, rel=1e-4)
    assert joint_move_profile(nudged, TARGET, 1.0, 2.0, 3.0).duration == 3.0
