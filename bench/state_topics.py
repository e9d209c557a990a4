"""State topics as a subscriber sees them: rate, inter-arrival times and sample age.

The three topics of the driver (``tool_position``, ``joint_position``, ``robot_states``) are
recorded together for one window. Per topic:

* rate (Hz) = (messages − 1) / (last − first receipt time);
* inter-arrival (ms) = differences of consecutive receipt times;
* sample age (ms) = receipt time − ``header.stamp`` (the time the sample was taken); the
  ``robot_states`` message (jaka_msgs/RobotMsg) has no header, so no age.
"""
from __future__ import annotations

import time
from contextlib import ExitStack

import numpy as np
from geometry_msgs.msg import TwistStamped
from sensor_msgs.msg import JointState

from jaka_msgs.msg import RobotMsg

from . import ros_session
from .report import REPORT, Row, at_most, judged
from .stats import fmt, summary

TOPICS = (("tool_position", TwistStamped), ("joint_position", JointState),
          ("robot_states", RobotMsg))
RATE_HZ, RATE_TOL_HZ = 125.0, 0.5
INTERARRIVAL_P99_MS = 10.0
AGE_P99_MS = 8.0


def record(driver, seconds: float, topics=TOPICS) -> dict:
    """Receipt times (s, wall clock) and stamps (s, or None) per topic of ``topics`` ((name,
    message type) pairs; default the state topics) over ``seconds``."""
    with ExitStack() as stack:
        recs = {name: ros_session.recorder(stack, driver.name(name), msg_type)
                for name, msg_type in topics}
        ros_session.wait_until(lambda: all(r.latest() is not None for r in recs.values()), 10.0)
        time.sleep(0.5)       # connections settled
        t0 = time.time()
        time.sleep(seconds)
        t1 = time.time()
        out = {}
        for name, rec in recs.items():
            got = [(t, m) for t, m in rec.since(t0) if t <= t1]
            out[name] = {
                "recv": np.array([t for t, _ in got]),
                "stamp": (np.array([m.header.stamp.to_sec() for _, m in got])
                          if dict(topics)[name]._has_header else None),
            }
    return out


def analyse(samples: dict) -> dict:
    """Rate, inter-arrival and age statistics per topic (see the module docstring)."""
    return analyse_windows([samples])


def analyse_windows(windows: list[dict]) -> dict:
    """:func:`analyse` of several windows of :func:`record` taken as one: intervals within
    each window only (never across the gap between two), the rate over their summed spans."""
    out = {}
    for name in windows[0]:
        parts = [w[name] for w in windows]
        n = sum(p["recv"].size for p in parts)
        intervals = sum(p["recv"].size - 1 for p in parts if p["recv"].size > 1)
        span = sum(p["recv"][-1] - p["recv"][0] for p in parts if p["recv"].size > 1)
        stats = {"messages": int(n), "rate_hz": intervals / span if span > 0 else 0.0,
                 "interarrival_ms": summary(np.concatenate([np.diff(p["recv"])
                                                             for p in parts]), 1e3)}
        if parts[0]["stamp"] is not None:
            stats["age_ms"] = summary(np.concatenate([p["recv"] - p["stamp"]
                                                      for p in parts]), 1e3)
            # Stamp intervals show whether the twin kept its 8 ms grid (a skipped cycle
            # is a gap); not when the node woke.
            stats["stamp_interval_ms"] = summary(np.concatenate([np.diff(p["stamp"])
                                                                 for p in parts]), 1e3)
        out[name] = stats
    return out


def _late_note(s: dict, what: str, value: float, machine_percent: float | None) -> str:
    """Why a p99 is late: skipped cycles (seen in the stamps) or the wake-ups on the way."""
    stamp = s.get("stamp_interval_ms", {}).get("p99")
    where = ""
    if stamp is not None:
        # A stamp is the cycle's time on the twin's 8 ms grid, not the time it was sent:
        # it shows skipped cycles, not when the node woke.
        where = (f"The stamps (the twin's cycle times) have intervals p99 {stamp:.1f} ms: "
                 + ("no cycle was skipped; the time is lost in the wake-ups on the way. "
                    if stamp < 1.5e3 / RATE_HZ else
                    "the twin skipped cycles (its physics thread stalled). "))
    load = (f"The machine was {machine_percent:.0f} % busy (of one core; 200 % = both) in "
            "this window. " if machine_percent is not None else "")
    return (f"{what} p99 {value:.1f} ms. {where}{load}A message reaches the subscriber "
            "after three wake-ups: the twin's physics thread at the cycle's end, the node's "
            "publisher, the subscriber's receive thread. The bare timer loop's row (same "
            "load, right after this window) shows what one wake-up at the default priority "
            "gets from this machine; the subscriber here runs at the default, as a user's "
            "would. The node's threads run at real-time priority (SCHED_FIFO 10) once it is "
            "ready where the system allows it, else at the default policy with a short time "
            "slice: its log's \"scheduling:\" line says which (jaka_driver.host.realtime). At "
            "the default policy a cycle's burst that a scheduler tick finds past its slice "
            "waits for the next tick (3-4 ms).")


def rows(group: str, condition: str, stats: dict, judge: bool = True,
         machine_percent: float | None = None) -> list[Row]:
    """Table rows for one window; ``judge`` False gives report-only rows (emulator path)."""
    out = []
    explained: dict[str, str] = {}   # kind → topic whose row carries the full explanation

    def verdict(ok: bool) -> str:
        return judged(ok) if judge else REPORT

    def once(kind: str, name: str, text: str) -> str:
        """The full note on the first topic that misses, a pointer to it on the others."""
        if not text:
            return ""
        if kind in explained:
            return f"same cause as {explained[kind]} {kind}, {condition}."
        explained[kind] = name
        return text

    for name, s in stats.items():
        rate = s["rate_hz"]
        ok = abs(rate - RATE_HZ) <= RATE_TOL_HZ
        note = "" if ok or not judge else (
            f"{rate:.2f} Hz (longest gap {s['interarrival_ms']['max']:.0f} ms): every cycle "
            "is published, also those caught up after a stall, unless the twin stalled for "
            "more than 0.2 s (it then skips ahead) or the publisher fell more than 32 cycles "
            "behind. Same causes and fixes as the inter-arrival tail below.")
        note = once("rate", name, note)
        out.append(Row(group, f"{name} rate, {condition}", f"{rate:.2f} Hz "
                       f"({s['messages']} msgs)", f"{RATE_HZ:g} ± {RATE_TOL_HZ:g} Hz",
                       verdict(ok), note, data=s,
                       bounds=at_most(abs(rate - RATE_HZ), RATE_TOL_HZ, "Hz", "off 125 Hz")
                       if judge else []))
    for name, s in stats.items():
        ia = s["interarrival_ms"]
        ok = ia["p99"] is not None and ia["p99"] <= INTERARRIVAL_P99_MS
        note = once("inter-arrival", name, "" if ok or not judge else _late_note(
            s, "inter-arrival", ia["p99"], machine_percent))
        out.append(Row(group, f"{name} inter-arrival p50 / p99 / max, {condition}",
                       f"{fmt(ia['p50'])} / {fmt(ia['p99'])} / {fmt(ia['max'])} ms",
                       f"p99 ≤ {INTERARRIVAL_P99_MS:g} ms", verdict(ok), note,
                       data={"interarrival_ms": ia},
                       bounds=at_most(ia["p99"], INTERARRIVAL_P99_MS, "ms", "p99")
                       if judge else []))
    for name, s in stats.items():
        if "age_ms" not in s:
            continue
        age = s["age_ms"]
        ok = age["p99"] is not None and age["p99"] <= AGE_P99_MS
        note = "" if ok or not judge else (
            f"p50 {age['p50']:.1f} ms: the usual path (publish at the end of the cycle + "
            "delivery) is short; the tail is the same scheduling delay as the inter-arrival "
            "tail, see there.")
        note = once("sample age", name, note)
        out.append(Row(group, f"{name} sample age p50 / p99 / max, {condition}",
                       f"{fmt(age['p50'])} / {fmt(age['p99'])} / {fmt(age['max'])} ms",
                       f"p99 ≤ {AGE_P99_MS:g} ms", verdict(ok), note,
                       bounds=at_most(age["p99"], AGE_P99_MS, "ms", "p99") if judge else []))
    return out
