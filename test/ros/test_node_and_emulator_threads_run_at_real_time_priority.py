"""Once ready, the threads of the cycle run at SCHED_FIFO 10 by default, every other thread at
the default policy (jaka_driver.host.realtime: a busy machine then no longer delays a cycle by a
scheduler tick): the twin's physics thread and the state publisher in the node on the twin, the
status reader and the publisher in the node on a controller, the twin and the status push in
the emulator. ``realtime_priority`` 0 leaves them at the default policy, with the short time
slice; a priority outside 0–99 stops the node (exit 2) or the emulator (a usage error) with the
value and the range; a twin in sim time keeps the default policy (at real_time_factor 0 it
would hold cores at real-time priority)."""
from __future__ import annotations

import os
import platform
import subprocess
import sys

import pytest

from support.ros_harness import DriverProcess, wait_until
from support.scheduling import may_use_fifo, thread_policies, thread_slices

from jaka_driver.emulator.process import EmulatorProcess

pytestmark = pytest.mark.ros

FIFO_10 = (os.SCHED_FIFO, 10)
DEFAULT = (os.SCHED_OTHER, 0)


def _ready_driver(request, **params) -> DriverProcess:
    driver = DriverProcess(log_name=f"realtime_{request.node.name}", backend="sim",
                           model="zu5", **params)
    request.addfinalizer(driver.stop)
    driver.wait_ready()
    return driver


def _needs_fifo():
    if not may_use_fifo():
        pytest.skip("this machine gives the tests neither CAP_SYS_NICE nor an rtprio limit")


def _fifo_and_others(pid: int) -> tuple[int, set]:
    """(threads at SCHED_FIFO 10, the set of the others' (policy, priority))."""
    policies = thread_policies(pid)
    fifo = [tid for tid, p in policies.items() if p == FIFO_10]
    return len(fifo), {p for p in policies.values() if p != FIFO_10}


def test_the_twin_node_s_physics_and_publisher_run_at_sched_fifo_10_once_ready(request,
                                                                             rospy_node):
    _needs_fifo()
    driver = _ready_driver(request)
    assert _fifo_and_others(driver.proc.pid) == (2, {DEFAULT})
    assert len(thread_policies(driver.proc.pid)) >= 5      # main, rospy's own... stay as they are
    assert ("scheduling: real-time priority SCHED_FIFO 10 for the cycle's threads (2 now, and "
            "those that start later)") in driver.log_path.read_text()


def _kernel_has_custom_slices() -> bool:
    """Linux 6.12 and later honour a SCHED_OTHER thread's own time slice."""
    major, minor = (int(x) for x in platform.release().split(".")[:2])
    return (major, minor) >= (6, 12)


def test_realtime_priority_0_leaves_every_thread_at_the_default_policy_with_the_short_slice(
        request, rospy_node):
    """The short slice (jaka_driver.host.latency_hint) is set once in the main thread before
    rospy and the twin start theirs, so the physics, publisher and service threads all wake as
    latency-sensitive; it is what remains without real-time priority."""
    driver = _ready_driver(request, realtime_priority=0)
    assert set(thread_policies(driver.proc.pid).values()) == {DEFAULT}
    log = driver.log_path.read_text()
    assert "scheduling: real-time priority off (realtime_priority 0)" in log
    slices = thread_slices(driver.proc.pid)
    if _kernel_has_custom_slices():
        assert len(slices) >= 5, slices         # main, physics, publisher, rospy's own...
        assert set(slices.values()) == {200_000}, slices
        assert "scheduling: time slice 0.2 ms" in log
    else:
        assert "scheduling: no short time slice: this kernel has no custom slices" in log


@pytest.mark.parametrize("priority", [100, -3, "high"])
def test_a_priority_outside_0_to_99_stops_the_node_with_value_and_range(request, rospy_node,
                                                                        priority):
    driver = DriverProcess(log_name=f"realtime_bad_{priority}", backend="sim", model="zu5",
                           realtime_priority=priority)
    request.addfinalizer(driver.stop)
    assert wait_until(lambda: not driver.alive(), 60.0), "the node started anyway"
    assert driver.proc.returncode == 2, driver.log()
    expected = (f"~realtime_priority {priority}; expected 0 (off) or 1–99 (SCHED_FIFO)"
                if isinstance(priority, int) else
                f"~realtime_priority {priority!r}; expected a whole number")
    assert expected in driver.log()
    assert "jaka_driver ready" not in driver.log()


def test_the_emulator_s_twin_and_status_push_and_the_node_s_status_reader_run_at_sched_fifo_10(
        request, rospy_node):
    _needs_fifo()
    emulator = EmulatorProcess("zu5").start()
    request.addfinalizer(emulator.stop)
    assert _fifo_and_others(emulator.proc.pid) == (2, {DEFAULT})
    driver = DriverProcess(log_name=f"realtime_{request.node.name}", backend="controller",
                           model="zu5", ip="127.0.0.1", command_port=emulator.command_port,
                           status_port=emulator.status_port)
    request.addfinalizer(driver.stop)
    driver.wait_ready()
    assert _fifo_and_others(driver.proc.pid) == (2, {DEFAULT})
    # a status reader that starts again, after the link was lost, starts at the priority
    emulator.stop()
    assert wait_until(lambda: _fifo_and_others(driver.proc.pid)[0] == 1, 10.0), \
        thread_policies(driver.proc.pid)              # the reader ended with its link
    restarted = EmulatorProcess("zu5", command_port=emulator.command_port,
                                status_port=emulator.status_port).start()
    request.addfinalizer(restarted.stop)
    assert wait_until(lambda: _fifo_and_others(driver.proc.pid) == (2, {DEFAULT}), 20.0), \
        thread_policies(driver.proc.pid)


def test_the_emulator_at_realtime_priority_0_keeps_the_default_policy(request):
    off = EmulatorProcess("zu5", "127.0.0.1", 0, 0, None, "--realtime-priority", "0").start()
    request.addfinalizer(off.stop)
    assert set(thread_policies(off.proc.pid).values()) == {DEFAULT}


def test_the_emulator_refuses_a_priority_outside_0_to_99():
    out = subprocess.run([sys.executable, "-m", "jaka_driver.emulator", "--realtime-priority",
                          "100"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 2
    assert "realtime_priority 100; expected 0 (off) or 1–99 (SCHED_FIFO)" in out.stderr
