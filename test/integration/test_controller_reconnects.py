"""Losing the controller and getting it back (docs/interface.md, "Backends"): services answer -1
within 1 s and never hang, the state says the link is down, the backend reconnects by itself within
5 s of the controller returning, and no motion command is replayed."""
from __future__ import annotations

import json
import socket
import threading
import time

import numpy as np
import pytest

from support.ros_harness import free_port, wait_until

from jaka_driver.backend.robot_state import MotionState
from jaka_driver.common.models import load_model
from jaka_driver.common.results import Code
from jaka_driver.controller import ControllerBackend
from jaka_driver.emulator import Emulator
from jaka_driver.emulator.process import EmulatorProcess
from support.move_helpers import run_move

HOME = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0])
FAR = HOME + np.array([1.2, 0, 0, 0, 0, 0])   # ~4 s at 0.3 rad/s: long enough to interrupt


def raw_call(port: int, name: str, **fields) -> dict:
    """One request on a fresh connection, no project code (for the emulator subprocess)."""
    with socket.create_connection(("127.0.0.1", port), timeout=2.0) as sock:
        sock.sendall(json.dumps({"cmdName": name, **fields}).encode())
        data = b""
        while True:
            data += sock.recv(65536)
            try:
                return json.loads(data)
            except ValueError:
                continue


class MoveInThread:
    """A blocking joint_move in its own thread, timing its answer."""

    def __init__(self, backend, target, speed=0.3):
        self.result = None
        self.answered = None
        self._thread = threading.Thread(target=self._run, args=(backend, target, speed))
        self._thread.start()

    def _run(self, backend, target, speed):
        self.result = run_move(backend.start_joint_move(target, speed, 1.0))
        self.answered = time.monotonic()

    def join(self, timeout):
        self._thread.join(timeout)
        return self.result


def services_answer_minus_1_quickly(backend):
    """Every kind of service, while the link is down: -1, each well within 1 s."""
    calls = {
        "joint_move": lambda: run_move(backend.start_joint_move(HOME, 0.5, 1.0)),
        "linear_move": lambda: run_move(backend.start_linear_move(np.eye(4), 0.1, 0.5)),
        "jog": lambda: backend.jog(0, 0, 1, 0.1),
        "servo_enable": lambda: backend.servo_enable(True),
        "servo_j": lambda: backend.servo_j(HOME),
        "stop_move": backend.stop_move,
        "set_io": lambda: backend.set_io("digital", 0, 0, 1.0),
        "get_io": lambda: backend.get_io("digital", 0, 0, 0),
        "set_tool_frame": lambda: backend.set_tool_frame(1, np.eye(4)),
        "set_payload": lambda: backend.set_payload(0, 1.0, np.zeros(3)),
        "set_collision_level": lambda: backend.set_collision_level(2),
        "clear_error": backend.clear_error,
        "set_drag_mode": lambda: backend.set_drag_mode(True),
        "forward_kinematics": lambda: backend.forward_kinematics(HOME),
        "set_power": lambda: backend.set_power(True),
    }
    for name, call in calls.items():
        t0 = time.monotonic()
        result = call()
        took = time.monotonic() - t0
        assert result.code == Code.NOT_CONNECTED, (name, result)
        assert "not connected" in result.message, (name, result.message)
        # Wall clock: a controller backend's refusal without a link is wall time (no sim
        # time on a controller). Resolution µs; 1 s is the bound on answering at once (no
        # wait for a connection) with room for a loaded machine's scheduling.
        assert took < 1.0, (name, took)


def assert_shows_the_loss(backend):
    st = backend.state()
    assert not st.connected
    assert not st.powered and not st.enabled and not st.moving
    assert st.motion_state == MotionState.ERROR
    assert time.time() - st.stamp < 0.1, "states keep coming, stamped now"


def lose_the_link_mid_move(backend, cut):
    """A long move runs and ``cut()`` breaks the link: the move answers -1 within 1 s of the cut
    and the state shows the loss. Returns (the move's result, when the cut happened)."""
    move = MoveInThread(backend, FAR)
    time.sleep(0.5)
    t_cut = time.monotonic()
    cut()
    result = move.join(2.0)
    assert result.code == Code.NOT_CONNECTED
    assert move.answered - t_cut < 1.0
    assert_shows_the_loss(backend)
    return result, t_cut


def test_dropped_connections(caplog):
    with Emulator("zu5", command_port=0, status_port=0) as emu:
        backend = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port)
        backend.start()
        try:
            assert backend.state().connected
            result, t_drop = lose_the_link_mid_move(backend, emu.drop_clients)
            assert "not resumed" in result.message
            services_answer_minus_1_quickly(backend)

            assert wait_until(lambda: backend.state().connected, 5.0)
            back_after = time.monotonic() - t_drop
            assert back_after < 5.0
            st = backend.state()
            assert st.powered and st.enabled
            # Nothing replayed: the one joint_move the emulator received is the original one.
            time.sleep(0.3)
            assert emu.handlers.counts["joint_move"] == 1
            assert backend.stop_move().ok   # the original move was accepted: stop it
            assert wait_until(lambda: not backend.state().moving, 2.0)
            assert run_move(backend.start_joint_move(HOME, 1.0, 4.0)).ok
            assert emu.handlers.counts["joint_move"] == 2
            lost = [r for r in caplog.records if "lost" in r.getMessage()
                    and r.name == "jaka_driver.controller.connection"]   # the link's, not the emulator's
            assert len(lost) == 1, "the loss is logged once"
        finally:
            backend.shutdown()


def test_controller_process_killed_and_restarted():
    ports = dict(command_port=free_port(), status_port=free_port())
    model = load_model("zu5")
    first = EmulatorProcess("zu5", **ports).start()
    second = None
    backend = ControllerBackend(model, "127.0.0.1", **ports)
    try:
        backend.start()
        assert backend.state().connected
        lose_the_link_mid_move(backend, first.kill)
        assert run_move(backend.start_joint_move(HOME, 0.5, 1.0)).code == Code.NOT_CONNECTED

        second = EmulatorProcess("zu5", **ports, start="off").start()
        t_back = time.monotonic()
        assert wait_until(lambda: backend.state().connected, 5.0)
        assert time.monotonic() - t_back < 5.0
        # The new controller received no motion, and its arm stays where it started.
        q0 = backend.state().joint_position
        time.sleep(0.5)
        counts = raw_call(ports["command_port"], "emulator_stats")["commands"]
        assert not {"joint_move", "moveL", "jog", "servo_j", "servo_p"} & set(counts), counts
        np.testing.assert_allclose(backend.state().joint_position, q0, atol=1e-5)
        # A rebooted controller comes up powered off (as the recorded Zu 5s did in two of
        # three sessions): power and enable are the user's, as after any reboot.
        assert not backend.state().powered
        assert backend.set_power(True).ok and backend.set_enabled(True).ok
        target = HOME + np.array([0.1, 0, 0, 0, 0, 0])
        result = run_move(backend.start_joint_move(target, 1.0, 4.0))
        assert result.ok, result.message
        assert np.max(np.abs(backend.state().joint_position - target)) <= 1e-3
    finally:
        backend.shutdown()
        first.stop()
        if second is not None:
            second.stop()


def test_start_without_a_controller_then_it_appears():
    ports = dict(command_port=free_port(), status_port=free_port())
    backend = ControllerBackend(load_model("zu5"), "127.0.0.1", **ports)
    emulator = None
    try:
        t0 = time.monotonic()
        backend.start()                       # nobody listens: starts anyway, disconnected
        assert time.monotonic() - t0 < 3.0
        assert not backend.state().connected
        assert run_move(backend.start_joint_move(HOME, 0.5, 1.0)).code == Code.NOT_CONNECTED
        emulator = Emulator("zu5", **ports).start()
        t_up = time.monotonic()
        assert wait_until(lambda: backend.state().connected, 5.0)
        assert time.monotonic() - t_up < 5.0
        assert wait_until(lambda: backend.state().enabled, 2.0)
    finally:
        backend.shutdown()
        if emulator is not None:
            emulator.stop()


@pytest.fixture(autouse=True)
def no_leaked_threads():
    before = set(threading.enumerate())
    yield
    wait_until(lambda: not (set(threading.enumerate()) - before), 3.0, 0.05)
    leaked = [t.name for t in set(threading.enumerate()) - before if t.is_alive()]
    assert not leaked, leaked
