"""The measurements that need a running driver node, in the order they run on it.

1. state topics for ``topic_s`` with the machine otherwise idle (node CPU measured alongside),
   then the bare timer loop of :mod:`bench.scheduler_floor` (what the machine allows);
2. the same with both cores loaded by :class:`bench.cpu_load.BusyLoad` (node CPU too);
3. servo_j round trip; 4. the servo sine stream (node CPU measured during it).

:func:`idle_side_by_side` measures several nodes' idle CPU over the same windows, for a
comparison the host's minute cannot tilt.

Every window also records the whole machine's CPU use, so a run disturbed by other programs
shows it.
"""
from __future__ import annotations

import time
from contextlib import ExitStack

from sensor_msgs.msg import JointState

from . import node_resources, ros_session, scheduler_floor, servo_latency, state_topics
from .cpu_load import BusyLoad
from .proc_meter import CpuWindow, MachineWindow
from .report import REPORT, Row

FLOOR_S = 10.0      # the bare loop's window: 1250 wake-ups


def _window(driver, seconds: float, loaded: bool):
    """The topics for ``seconds``, then the bare timer loop under the same load."""
    with ExitStack() as stack:
        if loaded:
            stack.enter_context(BusyLoad())
        with MachineWindow() as machine, CpuWindow(driver.proc.pid) as cpu:
            samples = state_topics.record(driver, seconds)
        floor = scheduler_floor.timer_loop(min(seconds, FLOOR_S))
    return samples, {**cpu.as_dict(), "machine_percent": machine.percent}, floor


def run(group: str, driver, calls, *, judge: bool, topic_s: float, servo_s: float,
        rtt_s: float = servo_latency.RTT_SECONDS, physics_percent: float | None = None,
        log=print) -> tuple[list, dict]:
    """Rows and raw data (for the plots) of one node; ``physics_percent`` see
    :func:`bench.node_resources.rows`."""
    rows, raw, cpu = [], {}, {}
    for condition, loaded in (("idle", False), ("both cores loaded", True)):
        log(f"  state topics, {condition}, {topic_s:g} s")
        samples, cpu[condition], floor = _window(driver, topic_s, loaded)
        stats = state_topics.analyse(samples)
        rows += state_topics.rows(group, condition, stats, judge=judge,
                                  machine_percent=cpu[condition]["machine_percent"])
        rows += scheduler_floor.rows(group, condition, scheduler_floor.analyse(floor),
                                     state_topics.INTERARRIVAL_P99_MS)
        raw[f"topics {condition}"] = samples
        raw[f"timer loop {condition}"] = floor
        raw[f"machine {condition}"] = cpu[condition]["machine_percent"]
    with ExitStack() as stack:
        joints = ros_session.recorder(stack, driver.name("joint_position"), JointState)
        log(f"  servo_j round trip, {rtt_s:g} s")
        rtt = servo_latency.round_trip(driver, calls, joints, rtt_s)
        log(f"  servo sine stream, {servo_s:g} s")
        with MachineWindow() as machine, CpuWindow(driver.proc.pid) as window:
            stream = servo_latency.sine_stream(driver, calls, joints, servo_s)
        cpu["servo streaming"] = {**window.as_dict(), "machine_percent": machine.percent}
    rows += servo_latency.rows(group, "idle", rtt, stream, judge=judge)
    raw["servo stream"] = stream
    raw["servo rtt"] = rtt
    rows += node_resources.rows(group, cpu, judge=judge, physics_percent=physics_percent)
    return rows, raw


def idle_side_by_side(drivers: dict, seconds: float) -> dict:
    """label → the node's CPU (``CpuWindow.as_dict()`` plus ``machine_percent``) of each of
    ``drivers`` (label → driver), all idle with their state topics subscribed (as in the idle
    window above), measured over one and the same window of ``seconds``. Apart, minutes
    from each other, the same node idle measured 3.5 % of a core in one run and 6.1 % in
    the next: the host's speed moves more than the difference two nodes' are compared by."""
    with ExitStack() as stack:
        recorders = [ros_session.recorder(stack, driver.name(name), msg_type)
                     for driver in drivers.values() for name, msg_type in state_topics.TOPICS]
        ros_session.wait_until(lambda: all(r.latest() is not None for r in recorders), 10.0)
        time.sleep(0.5)       # connections settled
        with MachineWindow() as machine, ExitStack() as meters:
            cpus = {label: meters.enter_context(CpuWindow(driver.proc.pid))
                    for label, driver in drivers.items()}
            time.sleep(seconds)
    return {label: {**cpu.as_dict(), "machine_percent": machine.percent}
            for label, cpu in cpus.items()}


SIDE_BY_SIDE = "node CPU idle, the controller backend and the twin side by side"


def side_by_side_row(group: str, cpu: dict) -> Row:
    """The report row of :func:`idle_side_by_side` for the controller backend's node and a
    twin's node (``cpu`` labels ``controller`` and ``twin``); bench.floor_targets judges it."""
    ctl, twin = cpu["controller"], cpu["twin"]
    return Row(group, SIDE_BY_SIDE,
               f"{ctl['cpu_percent']:.1f} % and the twin's {twin['cpu_percent']:.1f} % of one "
               f"core over the same {ctl['window_s']:.0f} s; machine "
               f"{ctl['machine_percent']:.0f} % of 1 core", "report", REPORT,
               data={"controller": ctl, "twin": twin})
