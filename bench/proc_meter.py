"""CPU and memory of a process from ``/proc/<pid>/stat`` and ``/proc/<pid>/status``.

CPU is user + system time of all the process's threads (``utime`` + ``stime``, fields 14 and
15 of ``stat``, in clock ticks), divided by wall-clock time: 100 % = one core fully busy.
:class:`ProcessCpuClock` reads the same time in nanoseconds, for windows too short for ticks.
"""
from __future__ import annotations

import ctypes
import os
import time

_TICK = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid: int) -> float:
    """CPU time (s) the process has used so far, all threads, user + system."""
    with open(f"/proc/{pid}/stat") as f:
        # The command name (field 2) may hold spaces: split after its closing parenthesis.
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICK   # fields 14, 15 overall


def status_kib(pid: int, key: str) -> int:
    """A ``kB`` field of ``/proc/<pid>/status`` (``VmRSS``, ``VmHWM``...), in KiB."""
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    raise KeyError(key)


class ProcessCpuClock:
    """CPU time (s) another process has used so far, all its threads (also those that ended),
    at nanosecond resolution: the kernel's CPU clock of the process (``clock_getcpuclockid``).
    ``/proc``'s clock ticks (10 ms) are too coarse for a window of 0.2 s at a few % of a core.
    Call it to read the clock."""

    def __init__(self, pid: int):
        clock_id = ctypes.c_int()
        err = ctypes.CDLL(None).clock_getcpuclockid(pid, ctypes.byref(clock_id))
        if err:                               # the error number itself, not -1 and errno
            raise OSError(err, f"clock_getcpuclockid({pid}): {os.strerror(err)}")
        self._id = clock_id.value

    def __call__(self) -> float:
        return time.clock_gettime(self._id)


class CpuWindow:
    """CPU use of ``pid`` between :meth:`start` and :meth:`stop` (or a ``with`` block)."""

    def __init__(self, pid: int):
        self.pid = pid
        self._t0 = self._c0 = 0.0
        self.percent = float("nan")    # % of one core
        self.seconds = 0.0             # wall-clock length of the window
        self.rss_mib = float("nan")    # resident memory at the end of the window
        self.peak_rss_mib = float("nan")

    def start(self) -> "CpuWindow":
        self._t0, self._c0 = time.monotonic(), cpu_seconds(self.pid)
        return self

    def stop(self) -> "CpuWindow":
        c1, t1 = cpu_seconds(self.pid), time.monotonic()
        self.seconds = t1 - self._t0
        self.percent = 100.0 * (c1 - self._c0) / self.seconds if self.seconds > 0 else 0.0
        self.rss_mib = status_kib(self.pid, "VmRSS") / 1024
        self.peak_rss_mib = status_kib(self.pid, "VmHWM") / 1024
        return self

    def as_dict(self) -> dict:
        return {"cpu_percent": self.percent, "window_s": self.seconds,
                "rss_mib": self.rss_mib, "peak_rss_mib": self.peak_rss_mib}

    def __enter__(self) -> "CpuWindow":
        return self.start()

    def __exit__(self, *exc) -> None:
        if exc[0] is None:
            self.stop()


def machine_busy_seconds() -> tuple[float, float]:
    """(busy CPU-seconds of the whole machine, all CPUs; wall time s) from ``/proc/stat``:
    busy = everything but idle and iowait. Two calls give the machine's load in between."""
    with open("/proc/stat") as f:
        ticks = [int(v) for v in f.readline().split()[1:]]
    idle = ticks[3] + (ticks[4] if len(ticks) > 4 else 0)
    return (sum(ticks) - idle) / _TICK, time.monotonic()


class MachineWindow:
    """Whole-machine CPU use (% of one core; 200 % = both cores of a 2-core machine) over a
    ``with`` block: tells whether other programs ran during a measurement."""

    def __init__(self):
        self.percent = float("nan")
        self._b0 = self._t0 = 0.0

    def __enter__(self) -> "MachineWindow":
        self._b0, self._t0 = machine_busy_seconds()
        return self

    def __exit__(self, *exc) -> None:
        b1, t1 = machine_busy_seconds()
        self.percent = 100.0 * (b1 - self._b0) / max(t1 - self._t0, 1e-9)


def _all_processes() -> dict[int, tuple[str, float]]:
    """pid → (command line, CPU seconds so far) of every process readable now."""
    out = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        pid = int(entry)
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace").strip()
            out[pid] = (cmd, cpu_seconds(pid))
        except (OSError, ValueError, IndexError):
            continue
    return out


class OtherPrograms:
    """Programs that ran through the whole benchmark without being part of it, and the CPU
    they took: processes alive both at :meth:`start` and at :meth:`stop` other than this one
    (everything the benchmark starts is gone again by then)."""

    def __init__(self, min_percent: float = 2.0):
        self.min_percent = min_percent
        self._before: dict = {}
        self._t0 = 0.0
        self.found: list[dict] = []

    def start(self) -> "OtherPrograms":
        self._before, self._t0 = _all_processes(), time.monotonic()
        return self

    def stop(self) -> list[dict]:
        after, seconds = _all_processes(), time.monotonic() - self._t0
        me = os.getpid()
        self.found = []
        for pid, (cmd, cpu) in after.items():
            if pid == me or pid not in self._before or self._before[pid][0] != cmd:
                continue
            percent = 100.0 * (cpu - self._before[pid][1]) / max(seconds, 1e-9)
            if percent >= self.min_percent:
                self.found.append({"pid": pid, "command": cmd[:120],
                                   "cpu_percent": round(percent, 1)})
        self.found.sort(key=lambda p: -p["cpu_percent"])
        return self.found
