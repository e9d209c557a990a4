"""Once ready, the periodic threads run at SCHED_FIFO 10 by default and the others at the default
policy (jaka_driver.host.realtime: a busy machine then no longer delays a cycle by a scheduler
tick): in the node the cycle's (the twin's physics thread or the controller's status reader, the
state publisher) and its watchers and slower topics, the main thread and the service threads
not; in the emulator its twin and status push; a status reader started again after a lost link
starts at the priority. ``realtime_priority`` 0 leaves them at the default policy, with the
short time slice; a priority outside 0–99 stops the node (exit 2) or the emulator (a usage
error) with the value and the range; a twin in sim time keeps the default policy (at
real_time_factor 0 it would hold cores at real-time priority)."""
from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from support.ros_harness import DriverProcess, wait_until
from support.scheduling import (kernel_has_custom_slices, may_use_fifo, thread_policies,
                                thread_slices)

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


def _fifo(pid: int) -> list[int]:
    """The threads of ``pid`` at SCHED_FIFO 10 (the others are checked to be at the default)."""
    policies = thread_policies(pid)
    assert {p for p in policies.values() if p != FIFO_10} == {DEFAULT}, policies
    return [tid for tid, p in policies.items() if p == FIFO_10]


def _said(log: str) -> int:
    """How many periodic threads the log's scheduling line says it switched."""
    match = re.search(r"scheduling: real-time priority SCHED_FIFO 10 for the periodic threads "
                      r"\((\d+) now, and those that start later\); the others at the default "
                      r"policy", log)
    assert match, log[-3000:]
    return int(match.group(1))


def test_the_twin_node_s_periodic_threads_run_at_sched_fifo_10_and_no_other(request,
                                                                          rospy_node):
    _needs_fifo()
    driver = _ready_driver(request)
    fifo = _fifo(driver.proc.pid)
    # physics, publisher, TF, program state, diagnostics, speed ratio, watchdogs, stream ends
    assert len(fifo) >= 8, fifo
    assert len(fifo) == _said(driver.log_path.read_text())
    assert driver.proc.pid not in fifo                      # the main thread
    assert len(thread_policies(driver.proc.pid)) > len(fifo) + 3   # rospy's own, services


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
    if kernel_has_custom_slices():
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
    assert len(_fifo(emulator.proc.pid)) == 2
    driver = DriverProcess(log_name=f"realtime_{request.node.name}", backend="controller",
                           model="zu5", ip="127.0.0.1", command_port=emulator.command_port,
                           status_port=emulator.status_port)
    request.addfinalizer(driver.stop)
    driver.wait_ready()
    ready = len(_fifo(driver.proc.pid))
    assert ready == _said(driver.log_path.read_text()) and ready >= 8
    # the status reader ends with its link; the one that starts when the link is back
    # starts at the priority
    emulator.stop()
    assert wait_until(lambda: len(_fifo(driver.proc.pid)) == ready - 1, 10.0), \
        thread_policies(driver.proc.pid)
    restarted = EmulatorProcess("zu5", command_port=emulator.command_port,
                                status_port=emulator.status_port).start()
    request.addfinalizer(restarted.stop)
    assert wait_until(lambda: len(_fifo(driver.proc.pid)) == ready, 20.0), \
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
