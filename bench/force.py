"""The force/torque sensor and force control through ROS, on the zu5 twin with its sensor over the
table of config/scenes/table.yaml (the twin on the wall clock, as a user runs it):

1. **wrench sample age** — ``~wrench``'s receipt time − ``header.stamp`` (the sample's time)
   with the sensor on, recorded together with ``joint_position`` in the same window: the state
   topics' own sample age is the floor the wrench is read beside (both are published by one
   thread from the same sample, the wrench right after the state topics); node CPU in the same
   window (sensor on, force control off: the idle beside which force control's CPU is read);
2. **constant-force step** — 10 N along the tool's z against the table, from standing just
   above it: the settle time (from ``enable_admittance`` until ``~wrench``'s Fz stays within
   10 ± 0.5 N, on the samples' own stamps) and the steady error (mean and standard deviation of
   Fz + 10 N over the last second of the window); node CPU while force control runs.
"""
from __future__ import annotations

import time
from contextlib import ExitStack

import numpy as np
from geometry_msgs.msg import WrenchStamped
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool, Trigger

from jaka_driver.common.models import repo_root
from jaka_driver_msgs.srv import SetAdmittance, SetComplianceType

from . import ros_session, state_topics
from .proc_meter import CpuWindow, MachineWindow
from .report import REPORT, Row, at_most, judged
from .stats import fmt, summary

GROUP = "Force/torque sensor and force control (zu5 twin with its sensor, through ROS)"
TABLE = str(repo_root() / "config" / "scenes" / "table.yaml")
#: targets: the wrench's sample age as the state topics' (bench.state_topics), the issue's
#: constant-force step (settled within 2 s, held to 10 ± 0.5 N), force control's CPU as the
#: servo stream's (bench.node_resources)
AGE_P99_MS = state_topics.AGE_P99_MS
SETTLE_S, HOLD_N = 2.0, 0.5
FORCE_CPU_PERCENT = 15.0
PRESS_N = 10.0
STEP_S = 4.0                # the step's window: settling, then the last second held


def _step(driver, calls, seconds: float) -> dict:
    """Constant force from standing above the table: (t since the enable, Fz) of every
    ``~wrench`` sample, by its stamp."""
    with ExitStack() as stack:
        rec = ros_session.recorder(stack, driver.name("wrench"), WrenchStamped)
        ros_session.wait_until(lambda: rec.latest() is not None, 10.0)
        start = time.time()
        reply = calls("enable_admittance", SetBool, data=True)
        if not reply.success:
            raise RuntimeError(f"enable_admittance: {reply.message}")
        time.sleep(seconds)
        got = [m for t, m in rec.since(start)]
    t = np.array([m.header.stamp.to_sec() for m in got]) - start
    fz = np.array([m.wrench.force.z for m in got])
    keep = t >= 0.0
    return {"t": t[keep], "fz": fz[keep]}


def run(driver, calls, seconds: float, log=print) -> list[Row]:
    """The rows (see the module) on ``driver``, a zu5 twin node with its sensor over the
    table."""
    if not calls("ft_sensor_enable", SetBool, data=True).success:
        raise RuntimeError("ft_sensor_enable refused")
    time.sleep(0.3)
    if not calls("zero_ftsensor", Trigger).success:
        raise RuntimeError("zero_ftsensor refused")
    log(f"  wrench and state topics, sensor on, {seconds:g} s")
    with MachineWindow() as machine, CpuWindow(driver.proc.pid) as idle:
        ages = state_topics.record(driver, seconds, (("wrench", WrenchStamped),
                                                     ("joint_position", JointState)))
    reply = calls("set_admittance", SetAdmittance, axis=2, opt=1, ft_user=40.0, ft_rebound=0.0,
                  ft_constant=PRESS_N)          # the tool's z
    if reply.ret != 1:
        raise RuntimeError(f"set_admittance: {reply.message}")
    if calls("set_compliance_type", SetComplianceType, sensor_compensation=True,
             compliance_type=1).ret != 1:
        raise RuntimeError("set_compliance_type refused")
    log(f"  constant force {PRESS_N:g} N against the table, {max(seconds, STEP_S):g} s")
    with MachineWindow() as machine_on, CpuWindow(driver.proc.pid) as force_on:
        step = _step(driver, calls, max(seconds, STEP_S))
    calls("disable_force_control", Trigger)
    return rows(ages, step, {**idle.as_dict(), "machine_percent": machine.percent},
                {**force_on.as_dict(), "machine_percent": machine_on.percent})


def rows(ages: dict, step: dict, idle_cpu: dict, force_cpu: dict) -> list[Row]:
    out = []
    wrench_age = summary(ages["wrench"]["recv"] - ages["wrench"]["stamp"], 1e3)
    state_age = summary(ages["joint_position"]["recv"] - ages["joint_position"]["stamp"], 1e3)
    ok = wrench_age["p99"] is not None and wrench_age["p99"] <= AGE_P99_MS
    out.append(Row(GROUP, "wrench sample age p50 / p99 / max, sensor on",
                   f"{fmt(wrench_age['p50'])} / {fmt(wrench_age['p99'])} / "
                   f"{fmt(wrench_age['max'])} ms ({ages['wrench']['recv'].size} msgs); "
                   f"joint_position in the same window (the floor) {fmt(state_age['p50'])} / "
                   f"{fmt(state_age['p99'])} / {fmt(state_age['max'])} ms",
                   f"p99 ≤ {AGE_P99_MS:g} ms", judged(ok),
                   "" if ok else "the wrench is published right after the state topics from "
                   "the same sample: its age is the state topics' plus the time to publish "
                   "them; a tail above the floor's is the same scheduling delay", data={
                       "wrench_age_ms": wrench_age, "joint_position_age_ms": state_age},
                   bounds=at_most(wrench_age["p99"], AGE_P99_MS, "ms", "p99")))
    t, fz = step["t"], step["fz"]
    outside = np.flatnonzero(np.abs(fz + PRESS_N) > HOLD_N)
    settled = float(t[outside[-1] + 1]) if outside.size and outside[-1] + 1 < t.size else (
        0.0 if not outside.size else float("inf"))
    held = fz[t > t[-1] - 1.0] if t.size else np.array([])
    error = held + PRESS_N
    out.append(Row(GROUP, f"constant-force step {PRESS_N:g} N against the table: settle time",
                   f"{settled:.3f} s ({t.size} samples)",
                   f"≤ {SETTLE_S:g} s to within ±{HOLD_N:g} N", judged(settled <= SETTLE_S),
                   "" if settled <= SETTLE_S else "Fz did not stay within the band",
                   data={"settle_s": settled}, bounds=at_most(settled, SETTLE_S, "s")))
    steady = float(np.mean(error)) if error.size else float("nan")
    spread = float(np.std(error)) if error.size else float("nan")
    worst = float(np.max(np.abs(error))) if error.size else float("nan")
    out.append(Row(GROUP, "constant-force step: steady error over the last second",
                   f"mean {steady:+.3f} N, std {spread:.3f} N, worst {worst:.3f} N",
                   f"worst ≤ {HOLD_N:g} N", judged(worst <= HOLD_N), "",
                   data={"mean_n": steady, "std_n": spread, "worst_n": worst},
                   bounds=at_most(worst, HOLD_N, "N", "worst")))
    for label, w, target in (("sensor on, force control off", idle_cpu, None),
                             ("constant force on", force_cpu, FORCE_CPU_PERCENT)):
        status = REPORT if target is None else judged(w["cpu_percent"] <= target)
        out.append(Row(GROUP, f"node CPU, {label}",
                       f"{w['cpu_percent']:.1f} % of one core; machine "
                       f"{w['machine_percent']:.0f} % of 1 core over {w['window_s']:.0f} s",
                       "report (beside the next)" if target is None else
                       f"≤ {target:g} % of one core (the servo stream's)", status, "", data=w,
                       bounds=[] if target is None else at_most(w["cpu_percent"], target, "%")))
    return out
