"""What this machine's scheduler allows any 125 Hz program: the floor under the state topics'
inter-arrival rows.

A bare loop: one thread in a process of its own at the default priority (nice 0, like the
node and the benchmark's subscriber), no ROS, no messages, no interpreter lock shared with
another thread. It sleeps to absolute 8 ms deadlines and notes when it woke. It runs in the
same condition as the topic window before it (idle, or both cores loaded by the same kind of
busy programs), right after it, so the two compare. A message on a state topic needs at least
one such wake-up on its way (the twin's physics thread, then its publisher, then the
subscriber's receive thread), so the topics' inter-arrival cannot beat this loop's.
"""
from __future__ import annotations

import gzip
import json
import subprocess
import sys

import numpy as np

from jaka_driver.common.constants import SERVO_CYCLE  # the twin's cycle, the topics' period

from .report import REPORT, Row
from .stats import fmt, summary


# Run with ``python -c``: only the standard library, so nothing but the loop is in the
# process. Prints one JSON object: each wake-up's lateness past its deadline (s) and the
# wake-up times (s, monotonic).
_LOOP = """
import json, sys, time
period, seconds = float(sys.argv[1]), float(sys.argv[2])
n = int(seconds / period)
woke, late = [], []
deadline = time.monotonic() + period
for _ in range(n):
    time.sleep(max(0.0, deadline - time.monotonic()))
    now = time.monotonic()
    woke.append(now)
    late.append(now - deadline)
    deadline += period
json.dump({"woke": woke, "late": late}, sys.stdout)
"""


def kernel_tick() -> str:
    """The kernel's tick rate and preemption model from ``/proc/config.gz`` (e.g. "250 Hz
    tick, preemption model none"), or "" where the kernel does not publish its config."""
    try:
        with gzip.open("/proc/config.gz", "rt") as f:
            config = dict(line.strip().split("=", 1) for line in f if line.startswith("CONFIG_"))
    except (OSError, ValueError):
        return ""
    hz = config.get("CONFIG_HZ")
    models = [m for m in ("NONE", "VOLUNTARY", "LAZY", "RT") if config.get(f"CONFIG_PREEMPT_{m}") == "y"]
    if config.get("CONFIG_PREEMPT") == "y" and not models:
        models = ["FULL"]
    try:        # a kernel built with PREEMPT_DYNAMIC may be booted into another model
        boot = [a.split("=", 1)[1] for a in open("/proc/cmdline").read().split()
                if a.startswith("preempt=")]
    except OSError:
        boot = []
    if boot and config.get("CONFIG_PREEMPT_DYNAMIC") == "y":
        models = [boot[0].upper()]
    parts = ([f"{hz} Hz tick"] if hz else []) + ([f"preemption model {models[0].lower()}"]
                                                 if models else [])
    return ", ".join(parts)


def timer_loop(seconds: float) -> dict:
    """Run the bare loop for ``seconds``; wake-up times and lateness (s) as arrays."""
    out = subprocess.run([sys.executable, "-c", _LOOP, str(SERVO_CYCLE), str(seconds)],
                         capture_output=True, text=True, timeout=seconds + 30, check=True)
    data = json.loads(out.stdout)
    return {"woke": np.array(data["woke"]), "late": np.array(data["late"])}


def analyse(loop: dict) -> dict:
    """Inter-arrival and lateness summaries (ms) of one run of the loop."""
    return {"interarrival_ms": summary(np.diff(loop["woke"]), 1e3),
            "late_ms": summary(loop["late"], 1e3)}


def rows(group: str, condition: str, stats: dict, target_ms: float) -> list[Row]:
    """One report-only row: the loop's inter-arrival, against the topics' ``target_ms``."""
    ia, late = stats["interarrival_ms"], stats["late_ms"]
    kernel = kernel_tick()
    beyond = ia["p99"] is not None and ia["p99"] > target_ms
    note = (f"Wake-ups late past their deadline p50 / p99 / max {fmt(late['p50'])} / "
            f"{fmt(late['p99'])} / {fmt(late['max'])} ms. "
            + (f"This loop alone misses the topics' p99 ≤ {target_ms:g} ms: in this window "
               "no program at the default priority could meet it, whatever it does between "
               "wake-ups, and a topic message waits for at least one such wake-up on its "
               "way. " if beyond else
               f"Within the topics' p99 ≤ {target_ms:g} ms: a topic row that misses it here "
               "loses the time in the node or in the subscriber, not in the machine's "
               "scheduler alone. ")
            + (f"Kernel: {kernel}. " if kernel else "")
            + "A thread at the default priority that wakes while every core runs a busy "
            "program can wait for the scheduler's next tick; at real-time priority "
            "(SCHED_FIFO) it runs at once.")
    return [Row(group, f"bare 125 Hz timer loop (no ROS) inter-arrival p50 / p99 / max, "
                f"{condition}", f"{fmt(ia['p50'])} / {fmt(ia['p99'])} / {fmt(ia['max'])} ms",
                "report (the floor)", REPORT, note, data=stats)]
