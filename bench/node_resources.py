"""Rows for the node's own CPU and memory (measured with :class:`bench.proc_meter.CpuWindow`
over the windows of :mod:`bench.node_suite`)."""
from __future__ import annotations

from .report import REPORT, Row, judged

CPU_TARGET_PERCENT = 25.0


def rows(group: str, windows: dict, judge: bool = True,
         physics_percent: float | None = None) -> list[Row]:
    """``windows``: condition → ``CpuWindow.as_dict()`` plus ``machine_percent``.
    ``physics_percent``: what the twin's 1 kHz physics alone costs (% of a core, from
    :mod:`bench.twin_physics`), to split the node's CPU in the note."""
    out = []
    for condition, w in windows.items():
        judged_here = judge and condition != "both cores loaded"
        status = judged(w["cpu_percent"] <= CPU_TARGET_PERCENT) if judged_here else REPORT
        note = ""
        if status == "FAIL":
            physics = ("" if physics_percent is None else
                       f", against {physics_percent:.0f} % for the twin's 1000 physics steps "
                       "a second themselves (twin physics row)")
            note = (f"{w['cpu_percent']:.0f} % of a core{physics}, the machine being "
                    f"{w['machine_percent']:.0f} % busy (of one core). Most of the node's CPU "
                    "is Python overhead around the work: 125 wake-ups a second of the "
                    "physics loop, each running 8 steps of a servo law in numpy, and 125 "
                    "times a second an FK, four messages built, serialised and each handed to "
                    "a rospy queue thread per subscriber; contention for the interpreter lock "
                    "grows it on a busy machine. Fixes: the servo law inside MuJoCo (position "
                    "actuators with gravity compensation) so a cycle is one "
                    "mj_step(m, d, nstep=8) call, and publishing without per-connection "
                    "queues (queue_size=None) or from a C++ node.")
        out.append(Row(group, f"node CPU and RSS, {condition}",
                       f"{w['cpu_percent']:.1f} % of one core, RSS {w['rss_mib']:.0f} MiB "
                       f"(peak {w['peak_rss_mib']:.0f} MiB); machine {w['machine_percent']:.0f} %"
                       f" of 1 core over {w['window_s']:.0f} s",
                       f"≤ {CPU_TARGET_PERCENT:g} % of one core at 125 Hz; RSS reported"
                       if judged_here else "report", status, note, data=w))
    return out
