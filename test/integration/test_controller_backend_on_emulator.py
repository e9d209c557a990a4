"""The controller backend does what docs/interface.md says, against the emulator over real TCP:
moves arrive, blocking moves block and can be stopped, settings reach the controller and read
back, drag mode goes on and off; and it reads what it needs from every profile's packet."""
from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from support.ros_harness import wait_until

from jaka_driver.backend.robot_state import MotionState
from jaka_driver.common.results import Code
from jaka_driver.common.transforms import pose_mm_to_matrix
from jaka_driver.controller import ControllerBackend
from jaka_driver.driver import RobotDriver
from jaka_driver.emulator import Emulator
from jaka_driver.emulator.profiles import PROFILES
from jaka_driver.motion.profiles import SyncJointProfile
from jaka_driver.motion.trajectory import JointTrajectory
from support.emulated_arm import CATCH_UP, LINK_TIMEOUTS, planned_moves
from support.move_helpers import run_move

HOME = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0])


@pytest.fixture(scope="module")
def backend(emu):
    b = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                          **LINK_TIMEOUTS)
    b.start()
    yield b
    b.shutdown()


def twin_q(emu) -> np.ndarray:
    return emu.backend.state().joint_position


def go_home(backend):
    result = run_move(backend.start_joint_move(HOME, 2.0, 8.0))
    assert result.ok, result.message


def test_state_follows_the_status_stream(emu, backend):
    st = backend.state()
    assert st.connected and st.powered and st.enabled and not st.servo_mode
    assert st.motion_state == MotionState.STOP
    np.testing.assert_allclose(st.joint_position, twin_q(emu), atol=1e-4)
    np.testing.assert_allclose(st.tcp_pose, emu.backend.state().tcp_pose, atol=1e-5)
    assert time.time() - st.stamp < 0.1
    # effort is the joint torque of each monitor_data row: the twin's drives holding the arm
    held = emu.backend.state().joint_effort
    assert abs(st.joint_effort[1]) > 1.0
    np.testing.assert_allclose(st.joint_effort, held, rtol=0.05, atol=0.5)


def test_start_powers_on_and_enables_like_jakas_driver(emu):
    emu.controller.set_power(False)
    assert not emu.backend.state().powered
    fresh = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                              **LINK_TIMEOUTS)
    try:
        fresh.start()
        st = fresh.state()
        assert st.powered and st.enabled
        assert emu.backend.state().powered and emu.backend.state().enabled
    finally:
        fresh.shutdown()


def test_joint_move_blocks_until_within_1e3_rad(emu, backend):
    target = HOME + np.array([0.3, -0.2, 0.25, 0.1, -0.15, 0.2])
    t0 = time.monotonic()
    result = run_move(backend.start_joint_move(target, 1.0, 4.0))
    elapsed = time.monotonic() - t0
    assert result.ok, result.message
    assert np.max(np.abs(twin_q(emu) - target)) <= 1e-3
    assert np.max(np.abs(backend.state().joint_position - target)) <= 1e-3
    # Wall clock: the controller backend runs on the wall clock (the emulator's cycles are
    # wall time). A lower bound only (µs resolution): a blocking call cannot return before the
    # motion's 0.55 s (0.3 rad at 1 rad/s, 4 rad/s²); load only makes it later.
    assert elapsed > 0.55
    go_home(backend)


def test_joint_move_with_mvtime_takes_that_long(emu, backend):
    """The wire has no duration: the backend sends the speed at which the controller's own
    profile takes 1.5 s, so the emulator's twin plans 1.5 s (its plan, not the wall clock,
    which adds when the 30 ms packets tell the end); the wait covers the move it played."""
    target = HOME + np.array([0.2, 0, 0, 0, 0, 0])
    with planned_moves(emu.backend) as played:
        t0 = time.monotonic()
        result = run_move(backend.start_joint_move(target, 3.0, 8.0, duration=1.5))
        waited = time.monotonic() - t0
    assert result.ok, result.message
    assert played == [pytest.approx(1.5, abs=0.01)], played
    assert waited >= 1.5 - CATCH_UP, waited
    go_home(backend)


def test_a_too_short_mvtime_is_refused_once_at_the_door(emu, backend):
    """The driver refuses it naming mvtime; the backend never sees it (no second rule)."""
    driver = RobotDriver(backend)
    sent = emu.handlers.counts["joint_move"]
    too_short = driver.joint_move((HOME + np.array([2.0, 0, 0, 0, 0, 0])).tolist(), 1.0, 4.0,
                                  mvtime=0.5)
    assert too_short.code == Code.INVALID_PARAMETER and "mvtime is 0.500 s" in too_short.message
    assert emu.handlers.counts["joint_move"] == sent


def test_linear_move_reaches_the_pose(emu, backend):
    start = backend.state().tcp_pose
    target = start.copy()
    target[:3, 3] += [0.05, -0.03, 0.02]
    result = run_move(backend.start_linear_move(target, 0.2, 1.0))
    assert result.ok, result.message
    reached = emu.backend.state().tcp_pose
    assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) < 1e-3
    go_home(backend)


def test_jog_moves_until_jog_stop(emu, backend):
    q0 = twin_q(emu)
    t0 = time.monotonic()
    assert backend.jog(0, 0, +1, 0.3).ok      # ROS coord 0 = joint (wire coord_map 1)
    time.sleep(0.6)
    assert backend.state().moving
    assert backend.jog_stop().ok
    jogged = time.monotonic() - t0             # from before the jog to after its stop
    assert wait_until(lambda: not backend.state().moving, 2.0)
    moved = twin_q(emu)[0] - q0[0]
    # at 0.3 rad/s for at least the 0.6 s slept less the ramps, at most for as long as the jog
    # was on (a busy machine can lengthen the sleep) and its ramp down (0.05 rad)
    assert 0.08 < moved < 0.3 * jogged + 0.05, (moved, jogged)
    q1 = twin_q(emu)
    time.sleep(0.2)
    assert np.max(np.abs(twin_q(emu) - q1)) < 1e-3, "stopped for good"
    x0 = emu.backend.state().tcp_pose[0, 3]
    assert backend.jog(1, 0, -1, 0.05).ok      # ROS coord 1 = base X, negative
    time.sleep(0.5)
    assert backend.jog_stop().ok
    assert wait_until(lambda: not backend.state().moving, 2.0)
    assert emu.backend.state().tcp_pose[0, 3] < x0 - 0.01
    go_home(backend)


def test_servo_j_stream(emu, backend):
    assert backend.servo_enable(True).ok
    try:
        assert wait_until(lambda: backend.state().servo_mode, 2.0)
        q = twin_q(emu).copy()
        for _ in range(60):
            q[5] += 0.004
            assert backend.servo_j(q).ok
            time.sleep(0.008)
        assert wait_until(lambda: np.max(np.abs(twin_q(emu) - q)) <= 1e-3, 1.0)
        blocked = run_move(backend.start_joint_move(HOME, 1.0, 4.0))
        assert blocked.code == Code.CONTROLLER_REJECTED and "servo mode" in blocked.message
    finally:
        assert backend.servo_enable(False).ok
    assert not backend.state().servo_mode
    rejected = backend.servo_j(q)
    # fw 1.5.14 answers "-1" outside servo mode (recorded): servo mode off
    assert rejected.code == Code.SERVO_MODE_OFF and "servo" in rejected.message
    go_home(backend)


def test_servo_p_follows_a_pose(emu, backend):
    assert backend.servo_enable(True).ok
    try:
        pose = backend.state().tcp_pose.copy()
        for _ in range(40):
            pose[2, 3] += 0.0005
            assert backend.servo_p(pose).ok
            time.sleep(0.008)
        assert wait_until(lambda: abs(emu.backend.state().tcp_pose[2, 3] - pose[2, 3]) < 2e-4, 1.0)
    finally:
        backend.servo_enable(False)
    go_home(backend)


def test_stop_move_makes_a_blocking_move_return_minus_12(emu, backend):
    outcome = {}

    def move():
        outcome["result"] = run_move(backend.start_joint_move(
            HOME + np.array([1.0, 0, 0, 0, 0, 0]), 0.4, 2.0))
        outcome["at"] = time.monotonic()

    mover = threading.Thread(target=move)
    mover.start()
    time.sleep(0.6)
    assert backend.state().moving
    t_stop = time.monotonic()
    assert backend.stop_move().ok
    mover.join(2.0)
    assert outcome["result"].code == Code.MOTION_STOPPED
    assert "stopped by stop_move" in outcome["result"].message
    # at once, not at the move's end (1.9 s later): the stop, the next 30 ms status packets
    # and a busy machine's scheduling
    assert outcome["at"] - t_stop < 1.0, outcome["at"] - t_stop
    assert wait_until(lambda: not backend.state().moving, 1.0)
    assert twin_q(emu)[0] < HOME[0] + 0.5, "the arm stopped short of the target"
    go_home(backend)


def test_protective_stop_ends_a_blocking_move_and_clear_error_recovers(emu, backend):
    outcome = {}
    mover = threading.Thread(target=lambda: outcome.setdefault(
        "result", run_move(backend.start_joint_move(
            HOME + np.array([0.8, 0, 0, 0, 0, 0]), 0.4, 2.0))))
    mover.start()
    time.sleep(0.4)
    emu.controller.protective_stop("collision on link 3 (injected)")
    mover.join(2.0)
    assert outcome["result"].code == Code.MOTION_STOPPED
    assert "protective stop" in outcome["result"].message
    st = wait_until(lambda: backend.state() if backend.state().protective_stop else None, 2.0)
    assert st.collision and st.motion_state == MotionState.ERROR
    assert backend.clear_error().ok
    assert wait_until(lambda: not backend.state().in_error, 2.0)
    go_home(backend)


def test_frames_collision_and_kinematics(emu, backend):
    tool = pose_mm_to_matrix([0, 0, 100, 0, 0, np.pi / 2])
    user = pose_mm_to_matrix([300, -200, 50, 0, 0, 0.3])
    try:
        assert backend.set_tool_frame(2, tool).ok
        assert backend.set_user_frame(3, user).ok
        assert (emu.backend.state().tool_id, emu.backend.state().user_id) == (2, 3)
        np.testing.assert_allclose(emu.backend.frames()[0], tool, atol=1e-9)
        np.testing.assert_allclose(emu.backend.frames()[1], user, atol=1e-9)
        assert wait_until(lambda: (backend.state().tool_id, backend.state().user_id) == (2, 3),
                          2.0)
        got_tool, got_user = backend.frames()
        np.testing.assert_allclose(got_tool, tool, atol=1e-9)
        np.testing.assert_allclose(got_user, user, atol=1e-9)

        q = HOME + np.array([0.1, -0.1, 0.2, 0.0, 0.1, 0.3])
        fk = backend.forward_kinematics(q)
        assert fk.ok
        np.testing.assert_allclose(fk.value, emu.backend.forward_kinematics(q).value, atol=1e-6)
        ik = backend.inverse_kinematics(fk.value, HOME)
        assert ik.ok
        np.testing.assert_allclose(ik.value, q, atol=1e-5)
        far = np.eye(4)
        far[:3, 3] = [5.0, 0, 0]
        assert backend.inverse_kinematics(far, HOME).code == Code.IK_FAILED

        assert backend.set_collision_level(3).ok and emu.backend.twin.collision_level == 3
        assert backend.set_collision_level(0).ok and emu.backend.twin.collision_level == 0
    finally:
        backend.set_tool_frame(0, np.eye(4))
        backend.set_user_frame(0, np.eye(4))
        backend.set_collision_level(2)
    assert (emu.backend.state().tool_id, emu.backend.state().user_id) == (0, 0)


def test_io_set_and_get(emu, backend):
    assert backend.set_io("digital", 0, 5, 1.0).ok
    assert backend.set_io("analog", 0, 0, 3.25).ok
    assert backend.set_io("digital", 1, 1, 1.0).ok
    emu.controller.set_input("digital", 0, 7, 1.0)
    emu.controller.set_input("analog", 0, 1, -1.5)
    assert backend.get_io("digital", 1, 0, 5).value == 1.0
    assert backend.get_io("digital", 1, 1, 1).value == 1.0
    assert backend.get_io("analog", 1, 0, 0).value == 3.25
    assert backend.get_io("digital", 0, 0, 7).value == 1.0
    assert backend.get_io("analog", 0, 0, 1).value == -1.5
    rejected = backend.set_io("digital", 0, 999, 1.0)
    # the controller names the wire index, one more than the driver's 0-based index 999
    assert rejected.code == Code.CONTROLLER_REJECTED and "index 1000" in rejected.message
    for signal, io_type, index in (("digital", 0, 5), ("analog", 0, 0), ("digital", 1, 1)):
        backend.set_io(signal, io_type, index, 0.0)
    emu.controller.set_input("digital", 0, 7, 0.0)
    emu.controller.set_input("analog", 0, 1, 0.0)


def test_extension_io_reads_back_on_a_cabinet_that_has_it(emu, backend):
    # the default profile's cabinet has an extension module (8/8 digital, 4/4 analog)
    try:
        assert backend.set_io("digital", 2, 3, 1.0).ok
        assert backend.get_io("digital", 1, 2, 3).value == 1.0
        assert backend.set_io("analog", 2, 1, 2.5).ok
        assert backend.get_io("analog", 1, 2, 1).value == 2.5
    finally:
        backend.set_io("digital", 2, 3, 0.0)
        backend.set_io("analog", 2, 1, 0.0)


def test_drag_mode_goes_on_and_off(emu, backend):
    result = backend.set_drag_mode(True)
    assert result.ok, result.message
    assert emu.backend.state().drag_mode and wait_until(lambda: backend.state().drag_mode, 1.0)
    assert backend.state().motion_state == MotionState.RUNNING   # hand guiding: not at rest
    assert backend.set_drag_mode(False).ok
    assert not emu.backend.state().drag_mode and wait_until(lambda: not backend.state().drag_mode, 1.0)
    assert backend.set_drag_mode(False).message == "drag mode already off"


def test_trajectory_is_streamed_with_servo_j(emu, backend):
    start = twin_q(emu).copy()
    goal = start + np.array([0.25, -0.1, 0.15, 0.0, 0.1, -0.2])
    trajectory = JointTrajectory.from_profile(
        SyncJointProfile(start, goal, emu.model.max_velocity * 0.5,
                         emu.model.max_acceleration * 0.5), 0.008)
    started = backend.start_trajectory(trajectory)
    assert started.ok, started.message
    completion, duration = started.value
    assert backend.state().servo_mode
    result = completion.wait(duration + 3.0)
    assert result is not None and result.ok, result
    assert np.max(np.abs(twin_q(emu) - goal)) <= 1e-3
    assert not backend.state().servo_mode and not emu.backend.state().servo_mode
    assert emu.handlers.counts["servo_j"] >= int(duration / 0.008)
    go_home(backend)


def test_stop_move_stops_a_trajectory(emu, backend):
    start = twin_q(emu).copy()
    trajectory = JointTrajectory.from_profile(
        SyncJointProfile(start, start + np.array([0.8, 0, 0, 0, 0, 0]),
                         emu.model.max_velocity * 0.3, emu.model.max_acceleration * 0.3), 0.008)
    completion, _ = backend.start_trajectory(trajectory).value
    time.sleep(0.5)
    assert backend.stop_move().ok
    result = completion.wait(1.0)
    assert result is not None and result.code == Code.MOTION_STOPPED
    assert wait_until(lambda: not backend.state().servo_mode, 1.0)
    go_home(backend)


def test_payload_reaches_the_controller(emu, backend):
    # Last in the module: the twin's payload update currently also resets its joint positions
    # (sim/twin_model.py, Payload.set → mj_setConst), which would disturb later tests.
    try:
        result = backend.set_payload(2, 2.5, np.array([0.0, 0.01, 0.05]))
        assert result.ok, result.message
        assert emu.controller.payload_mass == 2.5 and emu.backend.state().tool_id == 2
        np.testing.assert_allclose(emu.controller.payload_centroid_mm, [0, 10, 50])
        too_heavy = backend.set_payload(0, 50.0, np.zeros(3))
        assert too_heavy.code == Code.CONTROLLER_REJECTED and "mass" in too_heavy.message
    finally:
        backend.set_payload(0, 0.0, np.zeros(3))


@pytest.mark.parametrize("profile", list(PROFILES))
def test_the_backend_reads_what_it_needs_from_each_profiles_packet(profile):
    """Whichever keys a profile's packet carries, none the backend needs is missing: joints,
    TCP, joint torques, joint speeds (``instVel``, or from the joints where a packet has none),
    power, the frames in use, IO; a cabinet without an extension module refuses its IO."""
    with Emulator("zu5", command_port=0, status_port=0, profile=profile) as emu:
        b = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                              **LINK_TIMEOUTS)
        b.start()
        try:
            assert wait_until(lambda: abs(emu.backend.state().joint_effort[1]) > 1.0, 5.0)
            assert wait_until(lambda: b.view.latest is not None and b.state().enabled, 2.0)
            # the recorded fw 1.5.14 packet has no commanded joints (``joint_position``), which
            # the parser still lists as missing; the backend reads nothing of them
            expected = ("joint_position",) if profile == "zu5s-1.5.14" else ()
            assert b.view.latest.missing == expected, b.view.latest.missing
            st = b.state()
            assert st.powered and (st.tool_id, st.user_id) == (0, 0)
            np.testing.assert_allclose(st.joint_position, twin_q(emu), atol=1e-4)
            np.testing.assert_allclose(st.tcp_pose, emu.backend.state().tcp_pose, atol=1e-5)
            np.testing.assert_allclose(st.joint_effort, emu.backend.state().joint_effort,
                                       rtol=0.05, atol=0.5)
            # cruising at 0.5 rad/s (0.125 s ramps, 1.1 s in all): the speed the backend reports
            move = b.start_joint_move(twin_q(emu) + [0.5, 0, 0, 0, 0, 0], 0.5, 4.0)
            assert wait_until(lambda: abs(b.state().joint_velocity[0] - 0.5) < 0.05, 1.0)
            assert run_move(move).ok
            emu.controller.set_input("digital", 0, 3, 1.0)
            assert b.get_io("digital", 0, 0, 3).value == 1.0
            assert b.set_io("analog", 0, 2, 1.5).ok and b.get_io("analog", 1, 0, 2).value == 1.5
            extension = b.set_io("digital", 2, 0, 1.0)
            if emu.profile.io_sizes.get(("digital", 2, 1)):
                assert extension.ok and b.get_io("digital", 1, 2, 0).value == 1.0
            else:   # the recorded arm has no extension module: its controller refuses the IO
                assert extension.code == Code.CONTROLLER_REJECTED
                assert "no digital outputs" in extension.message
        finally:
            b.shutdown()
