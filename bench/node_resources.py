"""Rows for the node's own CPU and memory (measured with :class:`bench.proc_meter.CpuWindow`
over the windows of :mod:`bench.node_suite`)."""
from __future__ import annotations

from .report import REPORT, Row, at_most, judged

# % of one core: idle (the three state topics at 125 Hz, nothing else asked) and while
# servo_j streams at 125 Hz; the loaded window is reported only.
CPU_TARGET_PERCENT = {"idle": 10.0, "servo streaming": 15.0}


def rows(group: str, windows: dict, judge: bool = True,
         physics_percent: float | None = None) -> list[Row]:
    """``windows``: condition → ``CpuWindow.as_dict()`` plus ``machine_percent``.
    ``physics_percent``: what the twin's 1 kHz physics alone costs (% of a core, from
    :mod:`bench.twin_physics`), to split the node's CPU in the note."""
    out = []
    for condition, w in windows.items():
        target = CPU_TARGET_PERCENT.get(condition)
        judged_here = judge and target is not None
        status = judged(w["cpu_percent"] <= target) if judged_here else REPORT
        note = ""
        if status == "FAIL":
            physics = ("" if physics_percent is None else
                       f", of which the twin's physics (125 cycles of 8 steps a second) is "
                       f"{physics_percent:.0f} % (twin physics row)")
            note = (f"{w['cpu_percent']:.0f} % of a core{physics}, the machine being "
                    f"{w['machine_percent']:.0f} % busy (of one core). The rest is the "
                    "Python around it and the kernel's share of it: per 8 ms cycle two thread "
                    "wake-ups (physics, then the publisher it notifies), an FK for the TCP, "
                    "four messages refilled, serialised and written to each subscriber's "
                    "socket (bench.node_profile shows the split); on a busy machine each "
                    "wake-up and each interpreter-lock hand-over costs more. Left: the "
                    "publisher's work in the physics thread (one wake-up a cycle), or the "
                    "node in C++.")
        out.append(Row(group, f"node CPU and RSS, {condition}",
                       f"{w['cpu_percent']:.1f} % of one core, RSS {w['rss_mib']:.0f} MiB "
                       f"(peak {w['peak_rss_mib']:.0f} MiB); machine {w['machine_percent']:.0f} %"
                       f" of 1 core over {w['window_s']:.0f} s",
                       f"≤ {target:g} % of one core at 125 Hz; RSS reported"
                       if judged_here else "report", status, note, data=w,
                       bounds=at_most(w["cpu_percent"], target, "%") if judged_here else []))
    return out
