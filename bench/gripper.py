"""The DH gripper on the tool connector, on the wall clock as a user runs it:

1. **gripper command → fingers start moving** — from ``driver.gripper.move()`` being called to
   the end of the first cycle in which the twin's fingers have moved 0.1 mm (stamped in the
   physics thread's per-cycle hook, on the same monotonic clock: one process). On the twin
   (``SimBackend(gripper="dh_pgi")`` with a RobotDriver, no ROS) and through the emulator
   (``Emulator(gripper="dh_pgi")``, a RobotDriver on the controller backend: the frame goes out
   as ``send_tio_rs_command`` over TCP and reaches the emulator twin's gripper);
2. **grip-state sample age** — from the cycle in which the gripper's grip state becomes
   "reached" to the first ``driver.gripper.state()`` showing it (a watcher looking every
   millisecond): the TIO signal's poll (10 Hz, counted in cycles), plus, on the controller
   path, the status packet that carries it;
3. **node CPU with the gripper** — the node on the zu5 twin with ``gripper:=dh_pgi``,
   initialised and idle (its state watcher at 10 Hz and the finger joints with every sample on
   ``joint_states``), beside the sim group's idle row.

Not in the suite's tests: timings on a shared machine belong here.
"""
from __future__ import annotations

import time
from contextlib import ExitStack
from typing import Optional

import numpy as np

from jaka_driver.devices.register_maps import GripState

from .proc_meter import CpuWindow, MachineWindow
from .report import REPORT, Row, at_most, judged
from .stats import fmt, summary

GROUP = "Gripper on the tool connector (DH gripper, zu5 twin)"
#: the first motion within 3 cycles of the command on the twin: the frame is applied at once,
#: the fingers' reference ramps from the next cycle, the position loop answers within one more
MOTION_P99_MS = 3 * 8.0
#: a grip state is seen at most one signal poll (10 Hz) and a cycle after it changed
AGE_MAX_MS = 100.0 + 8.0
MOVED = 1e-4                  # m: the fingers have started moving
TARGETS = (0.03, 0.09)        # m: the openings the trials alternate between


class _Watch:
    """Stamps (``time.monotonic()``), in the physics thread's per-cycle hook, the first cycle
    after :meth:`arm` in which the fingers moved ``MOVED`` and the one in which the grip state
    became "reached"."""

    def __init__(self, physics, device):
        self.device = device
        self.armed = False
        self.start = 0.0
        self.moved: Optional[float] = None
        self.reached: Optional[float] = None
        physics.on_cycle.append(self._cycle)

    def arm(self) -> None:
        self.start = self.device.opening()
        self.moved = self.reached = None
        self.armed = True

    def _cycle(self, _d) -> None:
        if not self.armed:
            return
        now = time.monotonic()
        if self.moved is None and abs(self.device.opening() - self.start) > MOVED:
            self.moved = now
        if self.moved is not None and self.reached is None and \
                self.device.grip_state == GripState.REACHED:
            self.reached = now
            self.armed = False


def _trials(driver, watch: _Watch, n: int, log) -> dict:
    """``n`` moves between :data:`TARGETS`: command → motion and grip-state age (s each)."""
    gripper = driver.gripper
    motion, age = [], []
    for k in range(n):
        target = TARGETS[k % 2]
        watch.arm()
        t0 = time.monotonic()
        result = gripper.move(target)
        if not result.ok:
            raise RuntimeError(f"gripper move: {result.message}")
        seen = None
        deadline = t0 + 3.0
        while time.monotonic() < deadline:
            state = gripper.state()
            if watch.reached is not None and state.grip_state == GripState.REACHED and \
                    abs(state.opening - target) < 0.001:
                seen = time.monotonic()
                break
            time.sleep(0.001)
        if watch.moved is not None:
            motion.append(watch.moved - t0)
        if seen is not None and watch.reached is not None:
            age.append(seen - watch.reached)
        time.sleep(0.1)
    log(f"  {len(motion)} of {n} moves started, {len(age)} reached states seen")
    return {"motion_s": np.array(motion), "age_s": np.array(age), "trials": n}


def _ready(driver) -> None:
    gripper = driver.gripper
    for step in (gripper.set_up, gripper.initialise):
        result = step()
        if not result.ok:
            raise RuntimeError(f"gripper {step.__name__}: {result.message}")
    deadline = time.monotonic() + 5.0
    while not gripper.state().initialised:
        if time.monotonic() > deadline:
            raise RuntimeError("the gripper did not report initialised within 5 s")
        time.sleep(0.01)
    time.sleep(0.3)


def on_the_twin(trials: int, log=print) -> dict:
    from jaka_driver.common.models import load_model
    from jaka_driver.driver import RobotDriver
    from jaka_driver.sim import SimBackend
    backend = SimBackend(load_model("zu5"), gripper="dh_pgi")
    watch = _Watch(backend._physics, backend.tool_device)
    driver = RobotDriver(backend, gripper="dh_pgi")
    driver.start()
    try:
        _ready(driver)
        log(f"  twin: {trials} gripper moves")
        return _trials(driver, watch, trials, log)
    finally:
        driver.shutdown()


def through_the_emulator(trials: int, log=print) -> dict:
    from jaka_driver.controller import ControllerBackend
    from jaka_driver.driver import RobotDriver
    from jaka_driver.emulator import Emulator
    with Emulator("zu5", command_port=0, status_port=0, gripper="dh_pgi",
                  programs=None) as emu:
        watch = _Watch(emu.backend._physics, emu.backend.tool_device)
        backend = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port)
        driver = RobotDriver(backend, gripper="dh_pgi")
        driver.start()
        try:
            _ready(driver)
            log(f"  emulator: {trials} gripper moves")
            return _trials(driver, watch, trials, log)
        finally:
            driver.shutdown()


def node_cpu(stack: ExitStack, seconds: float, log=print) -> dict:
    """The node's CPU on the twin with the gripper mounted, initialised and idle."""
    from jaka_driver_msgs.srv import InitGripper

    from . import ros_session
    log("  gripper node: starting (zu5 twin, gripper:=dh_pgi)")
    driver = ros_session.start_driver(stack, "bench_gripper", backend="sim", model="zu5",
                                      gripper="dh_pgi")
    calls = ros_session.services(stack, driver)
    if calls("gripper/initialise", InitGripper, full_calibration=False).ret != 1:
        raise RuntimeError("gripper/initialise refused")
    time.sleep(1.0)
    log(f"  gripper node idle, {seconds:g} s")
    with MachineWindow() as machine, CpuWindow(driver.proc.pid) as cpu:
        time.sleep(seconds)
    return {**cpu.as_dict(), "machine_percent": machine.percent}


def measure(stack: ExitStack, trials: int, seconds: float, log=print) -> list[Row]:
    twin = on_the_twin(trials, log)
    emulator = through_the_emulator(trials, log)
    cpu = node_cpu(stack, seconds, log)
    return rows(twin, emulator, cpu)


def _latency_row(where: str, data: dict, target: Optional[float],
                 key: str, metric: str) -> Row:
    s = summary(data[key], 1e3)
    value = (f"{fmt(s['p50'])} / {fmt(s['p99'])} / {fmt(s['max'])} ms "
             f"({s['n']} of {data['trials']} moves)")
    if target is None:
        return Row(GROUP, f"{metric}, {where}", value, "report", REPORT, "", data=s)
    worst = s["max"] if key == "age_s" else s["p99"]
    ok = worst is not None and worst <= target and s["n"] == data["trials"]
    what = "max" if key == "age_s" else "p99"
    return Row(GROUP, f"{metric}, {where}", value, f"{what} ≤ {target:g} ms", judged(ok),
               "" if ok else "a move whose start or end was not seen counts as a miss",
               data=s, bounds=at_most(worst, target, "ms", what))


def rows(twin: dict, emulator: dict, cpu: dict) -> list[Row]:
    out = [
        _latency_row("twin", twin, MOTION_P99_MS, "motion_s",
                     "gripper command → fingers start moving p50 / p99 / max"),
        _latency_row("through the emulator (controller backend, TCP)", emulator, None,
                     "motion_s", "gripper command → fingers start moving p50 / p99 / max"),
        _latency_row("twin", twin, AGE_MAX_MS, "age_s",
                     "grip-state sample age p50 / p99 / max"),
        _latency_row("through the emulator (controller backend, TCP)", emulator, None,
                     "age_s", "grip-state sample age p50 / p99 / max"),
        Row(GROUP, "node CPU and RSS with the gripper (gripper:=dh_pgi, initialised, idle)",
            f"{cpu['cpu_percent']:.1f} % of one core, RSS {cpu['rss_mib']:.0f} MiB; machine "
            f"{cpu['machine_percent']:.0f} % of 1 core over {cpu['window_s']:.0f} s",
            "report (beside the sim group's idle row)", REPORT, "", data=cpu),
    ]
    return out
