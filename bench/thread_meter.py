"""Per-thread CPU and wake-ups of a process over a window, from ``/proc/<pid>/task/<tid>/``.

A thread's CPU is its ``utime`` + ``stime`` (``stat`` fields 14, 15, clock ticks); its wake-ups
are its context switches: ``voluntary_ctxt_switches`` (it blocked: a sleep, a lock, a socket
read — each one is a later wake-up) and ``nonvoluntary_ctxt_switches`` (the scheduler took the
core from it: another thread or program wanted it). Divided by the window's 8 ms cycles they
say how many times per sample a thread woke, which is what a chain of threads per sample costs
on a busy machine (each wake-up may wait for a core; each hand-over of the interpreter lock
is one more switch).

Python threads are named from py-spy's samples (``thread (tid): name``); others keep the
kernel's name (``comm``: "python" for all of a Python process's threads unless named).
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

from jaka_driver.common.constants import SERVO_CYCLE

_TICK = os.sysconf("SC_CLK_TCK")


def _read_task(pid: int, tid: str) -> tuple[float, int, int, str] | None:
    """(CPU s, voluntary, involuntary switches, comm) of one thread, None once it is gone."""
    base = f"/proc/{pid}/task/{tid}"
    try:
        with open(f"{base}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        vol = invol = 0
        with open(f"{base}/status") as f:
            for line in f:
                if line.startswith("voluntary_ctxt_switches:"):
                    vol = int(line.split()[1])
                elif line.startswith("nonvoluntary_ctxt_switches:"):
                    invol = int(line.split()[1])
        with open(f"{base}/comm") as f:
            comm = f.read().strip()
    except (OSError, ValueError, IndexError):
        return None
    return (int(fields[11]) + int(fields[12])) / _TICK, vol, invol, comm


def snapshot(pid: int) -> dict[int, tuple[float, int, int, str]]:
    """tid → (CPU s, voluntary, involuntary, comm) of every thread of ``pid`` now."""
    out = {}
    try:
        tids = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return out
    for tid in tids:
        got = _read_task(pid, tid)
        if got is not None:
            out[int(tid)] = got
    return out


@dataclass
class ThreadWindow:
    """What each thread of ``pid`` did between :meth:`start` and :meth:`stop`."""

    pid: int
    seconds: float = 0.0
    #: tid → {"cpu_percent", "voluntary", "involuntary", "comm"} over the window
    threads: dict = field(default_factory=dict)

    def start(self) -> "ThreadWindow":
        self._t0, self._s0 = time.monotonic(), snapshot(self.pid)
        return self

    def stop(self) -> "ThreadWindow":
        s1, t1 = snapshot(self.pid), time.monotonic()
        self.seconds = t1 - self._t0
        self.threads = {}
        for tid, (cpu, vol, invol, comm) in s1.items():
            c0, v0, i0, _ = self._s0.get(tid, (0.0, 0, 0, comm))
            self.threads[tid] = {"cpu_percent": 100.0 * (cpu - c0) / max(self.seconds, 1e-9),
                                 "voluntary": vol - v0, "involuntary": invol - i0,
                                 "comm": comm}
        return self

    @property
    def cycles(self) -> float:
        """The window's length in 8 ms cycles (samples of the state topics)."""
        return self.seconds / SERVO_CYCLE

    def rows(self, names: dict[int, str], top: int = 12) -> list[tuple[str, float, float, float]]:
        """(thread, CPU %, voluntary and involuntary switches per cycle), busiest first; the
        threads that neither ran nor woke are left out."""
        out = []
        for tid, t in self.threads.items():
            if t["voluntary"] == 0 and t["involuntary"] == 0 and t["cpu_percent"] == 0:
                continue
            name = names.get(tid) or f"[{t['comm']}]"
            out.append((f"{name} ({tid})", t["cpu_percent"], t["voluntary"] / self.cycles,
                        t["involuntary"] / self.cycles))
        out.sort(key=lambda r: -(r[1] + r[2] + r[3]))
        return out[:top]

    def total_per_cycle(self) -> float:
        """Context switches of all threads per cycle."""
        return sum(t["voluntary"] + t["involuntary"] for t in self.threads.values()) / \
            self.cycles
