"""The scheduling policy of a process's threads, and whether this machine lets the tests'
processes ask for real-time priority (jaka_driver.host.realtime)."""
from __future__ import annotations

import os
import platform
import resource
from pathlib import Path

CAP_SYS_NICE = 23


def kernel_has_custom_slices() -> bool:
    """Linux 6.12 and later honour a SCHED_OTHER thread's own time slice."""
    major, minor = (int(x) for x in platform.release().split(".")[:2])
    return (major, minor) >= (6, 12)


def may_use_fifo(priority: int = 10) -> bool:
    """A process started from here may set SCHED_FIFO ``priority``: CAP_SYS_NICE in effect, or
    an rtprio limit at least ``priority``."""
    with open("/proc/self/status") as f:
        caps = next(int(line.split()[1], 16) for line in f if line.startswith("CapEff:"))
    soft, _ = resource.getrlimit(resource.RLIMIT_RTPRIO)
    return bool(caps >> CAP_SYS_NICE & 1) or soft == resource.RLIM_INFINITY or soft >= priority


def thread_policies(pid: int) -> dict[int, tuple[int, int]]:
    """tid → (policy, priority) of every thread of ``pid`` (threads that end meanwhile are
    left out)."""
    out = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            out[int(task.name)] = (os.sched_getscheduler(int(task.name)),
                                   os.sched_getparam(int(task.name)).sched_priority)
        except ProcessLookupError:
            continue
    return out


def thread_slices(pid: int) -> dict[int, int]:
    """tid → time slice (ns, ``se.slice`` of /proc's ``sched``) of every thread of ``pid`` at
    the default policy (threads that end meanwhile are left out)."""
    out = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            sched = (task / "sched").read_text()
        except (FileNotFoundError, ProcessLookupError):
            continue
        if "se.slice" in sched:
            out[int(task.name)] = int(sched.split("se.slice")[1].split(":")[1].split()[0])
    return out
