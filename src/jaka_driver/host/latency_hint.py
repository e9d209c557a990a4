"""Tell the kernel that this process's threads are latency-sensitive: a short time slice.

The twin's physics, the state publisher and the service threads each wake many times a
second, run for a fraction of a millisecond and sleep again. When every core is busy with
other programs, Linux's fair scheduler (EEVDF, kernel 6.6 on) lets such a thread wait for the
running program's time slice to end, measured here up to a 4 ms scheduler tick per wake-up.
Since kernel 6.12 a thread may ask for a shorter slice (``sched_setattr`` with
``sched_runtime`` on SCHED_OTHER, 0.1–100 ms): its deadline comes sooner, so it is picked
first when it wakes. It gets no larger share of the CPU and needs no privilege, unlike
real-time priority. Older kernels accept the call and ignore the slice.

Measured on the 2-core development machine, the node's threads with and without it in one
running node, both cores loaded by busy programs for the latency (medians of paired 8–10 s
windows): state-topic inter-arrival p99 13.5 → 11.3 ms and sample age p99 6.8 → 4.6 ms (4
pairs; 13.7 → 12.4 and 6.7 → 5.9 in 5 earlier pairs). The price, idle: 513 instead of 287
context switches a second and 1.1–1.3 points more of a core (8.6 → 9.9 %, 10.7 → 11.8 % in
two sets of pairs): the publisher, woken by the physics thread, now runs at once and finds
the interpreter lock still held, so it sleeps again until the physics thread lets go. The
physics thread alone with the short slice costs nothing and gains nothing measurable.

Threads inherit the setting from the thread that starts them, so the scripts request it first
thing, before an import can start one (numpy's BLAS pool does); this module imports nothing
that starts threads.

It is what start-up runs with, and what remains where the system gives no real-time priority:
once ready, :mod:`.realtime` puts the threads at SCHED_FIFO where it may, which closes what no
slice length does (a burst that a tick finds past its slice waits for the next tick).
"""
from __future__ import annotations

import ctypes
import errno
import os
import platform

SLICE_S = 0.0002        # one wake-up's work in the node is 0.1–0.6 ms

# sched_setattr(2) has no wrapper in glibc 2.36 or in Python's os module.
_SYSCALL = {"x86_64": 314, "aarch64": 274, "riscv64": 274, "armv7l": 380, "armv6l": 380,
            "i686": 351, "ppc64le": 355}
_outcome: str | None = None     # the first request's, for the log


class _SchedAttr(ctypes.Structure):
    """``struct sched_attr`` (include/uapi/linux/sched/types.h), version 1 (56 bytes)."""
    _fields_ = [("size", ctypes.c_uint32), ("sched_policy", ctypes.c_uint32),
                ("sched_flags", ctypes.c_uint64), ("sched_nice", ctypes.c_int32),
                ("sched_priority", ctypes.c_uint32), ("sched_runtime", ctypes.c_uint64),
                ("sched_deadline", ctypes.c_uint64), ("sched_period", ctypes.c_uint64),
                ("sched_util_min", ctypes.c_uint32), ("sched_util_max", ctypes.c_uint32)]


def current_slice_s(path: str = "/proc/thread-self/sched") -> float | None:
    """A thread's time slice (s) from its ``sched`` file in /proc (default: the calling
    thread's); None where the kernel does not show it (built without scheduler debug)."""
    try:
        with open(path) as f:
            for line in f:
                if line.startswith("se.slice"):
                    return int(line.split(":")[1]) * 1e-9
    except (OSError, ValueError):
        pass
    return None


def request_short_slice(slice_s: float = SLICE_S) -> str:
    """Ask for a ``slice_s`` time slice for the calling thread (and the threads it starts
    from now on), keeping its policy SCHED_OTHER and its nice value. Returns a sentence for
    the log; never raises (the hint is an optimisation, the node runs without it). Once per
    process: a second call returns the first one's sentence."""
    global _outcome
    if _outcome is None:
        try:
            _outcome = _request(slice_s)
        except (OSError, AttributeError) as exc:   # no libc to load, no sched_* in os
            _outcome = f"no short time slice: {exc}"
    return _outcome


def _request(slice_s: float) -> str:
    number = _SYSCALL.get(platform.machine())
    if number is None:
        return f"no short time slice: sched_setattr is not known on {platform.machine()}"
    policy = os.sched_getscheduler(0)
    if policy in (os.SCHED_FIFO, os.SCHED_RR):
        # Started at real-time priority (chrt): that wakes sooner still; do not undo it.
        return "no short time slice: the process runs at real-time priority already"
    if policy != os.SCHED_OTHER:
        return f"no short time slice: the process was started with scheduling policy {policy}"
    attr = _SchedAttr(size=ctypes.sizeof(_SchedAttr), sched_policy=os.SCHED_OTHER,
                      sched_nice=os.getpriority(os.PRIO_PROCESS, 0),
                      sched_runtime=int(round(slice_s * 1e9)))
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.syscall(number, 0, ctypes.byref(attr), 0) != 0:
        err = ctypes.get_errno()
        return f"no short time slice: sched_setattr failed ({errno.errorcode.get(err, err)})"
    got = current_slice_s()
    if got is None:
        return (f"time slice {slice_s * 1e3:g} ms requested for this process's threads (the "
                "kernel does not show whether it applies)")
    if abs(got - slice_s) > 1e-6:
        return "no short time slice: this kernel has no custom slices (before 6.12)"
    return f"time slice {got * 1e3:g} ms for this process's threads (latency-sensitive)"
