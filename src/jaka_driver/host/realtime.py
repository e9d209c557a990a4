"""Real-time priority (``SCHED_FIFO``) for a process's periodic threads, where the system allows
it.

A driver's cycle — the twin's physics step or a controller's status packet, then the state
topics — is a burst of 0.1–0.5 ms every 8 ms. When other programs keep every core busy, the
fair scheduler lets such a burst run for its time slice and then, at the next scheduler tick,
gives the core back to the busy program until the tick after: 3–4 ms later (HZ 250). Measured
on the 2-core development machine, both cores loaded by busy programs, the twin's state topics
received by a subscriber at the default priority, 10 s windows, one fresh node each:

* the default policy, with the short slice of :mod:`.latency_hint` or any other (0.2, 0.5, 0.7,
  1, 3 and 10 ms; nice -5 and -10): inter-arrival p99 8.2–13.4 ms (55 nodes, 38 of them over
  10 ms), sample age p99 up to 6 ms, ~9 % of the cycles one tick late;
* the cycle's threads alone at ``SCHED_FIFO`` 10: 8.2–10.2 ms (14 nodes, median 8.9);
* the periodic threads at ``SCHED_FIFO`` 10 (below): 8.2–9.3 ms (6 nodes, median 8.4, paired
  with 6 of the former: lower in 5), the bare timer loop of ``bench/scheduler_floor.py`` 8.0 ms.

No time slice length at the default policy closes it: a slice short enough to be picked at
once on waking is too short to finish the burst before a tick.

A ``SCHED_FIFO`` thread runs as soon as it wakes and keeps its core until it sleeps again, ahead
of every thread at the default policy. So only the periodic threads get it, each of which wakes
on the cycle or a period of its own, does a bounded piece of work and sleeps again: the cycle's
(the twin's physics thread or a controller's status reader, the state publisher, a servo or
twist stream to a controller, the emulator's twin and status push) and the node's own watchers
and slower topics (TF of the frames, program state, diagnostics, the speed ratio, the force
state, the jog watchdog, a stream's end). They share the interpreter lock: one left at the
default policy and preempted while it holds the lock holds up the others until it runs again.
Service threads, whose work a client decides (a long plan, a fuzzer's calls back to back), stay
at the default policy: at real-time priority they could hold cores from the machine. Tried and
not kept: every thread of the node at SCHED_FIFO (loaded p99 8.2–8.6 ms in 10 nodes); the test
suite then ran 50 % longer, and with three suites' nodes side by side a move's wait woke 12–14 s
late behind main threads at SCHED_FIFO using 80 % of a core each, which an idle node's main
thread does not. The kernel's real-time throttling (0.95 s of each second by default,
``/proc/sys/kernel/sched_rt_runtime_us``) still leaves the other programs a share should a
periodic thread ever spin. It takes a privilege: root, ``CAP_SYS_NICE``, or an ``rtprio`` limit
at least the priority (``ulimit -r``; ``/etc/security/limits.d/``, e.g. ``@robot - rtprio
20``); without it the threads keep the short slice and the log says how to allow it.

A periodic thread runs its loop inside :func:`periodic_thread` (or its target is decorated with
:func:`runs_periodically`), which registers it; the process asks with :func:`request_realtime`
once it is ready, so that start-up (imports, model building) runs at the default policy: the
periodic threads registered then are switched, and one that starts later (a reconnected status
reader, a new servo stream) switches itself as it registers.
"""
from __future__ import annotations

import functools
import os
import resource
import threading
from contextlib import contextmanager
from typing import Callable, Iterator, TypeVar

F = TypeVar("F", bound=Callable)

#: the node's and the emulator's default priority: above every program at the default policy,
#: below the kernel's own real-time threads (interrupt threads run at 50)
DEFAULT_PRIORITY = 10

_lock = threading.Lock()
_periodic_threads: set[int] = set()  # native ids of the running periodic threads
_granted = 0                        # the priority granted by request_realtime, 0: none


def priority_error(priority: int) -> str | None:
    """Why ``priority`` is not one to ask for (None if it is): 0 = off, else
    ``SCHED_FIFO``'s 1–99."""
    highest = os.sched_get_priority_max(os.SCHED_FIFO)
    if priority == 0 or 1 <= priority <= highest:
        return None
    return f"realtime_priority {priority}; expected 0 (off) or 1–{highest} (SCHED_FIFO)"


@contextmanager
def periodic_thread() -> Iterator[None]:
    """Run the calling thread's loop as one of the periodic threads: at the granted real-time
    priority once :func:`request_realtime` has granted one (at once if it has), registered until
    the block ends. Never raises for the priority."""
    tid = threading.get_native_id()
    with _lock:
        _periodic_threads.add(tid)
        if _granted:
            _set_fifo(tid, _granted)
    try:
        yield
    finally:
        with _lock:
            _periodic_threads.discard(tid)


def runs_periodically(target: F) -> F:
    """Decorator of a periodic thread's target: it runs inside :func:`periodic_thread`."""
    @functools.wraps(target)
    def run(*args, **kwargs):
        with periodic_thread():
            return target(*args, **kwargs)
    return run  # type: ignore[return-value]


def request_realtime(priority: int = DEFAULT_PRIORITY) -> str:
    """Put the periodic threads (:func:`periodic_thread`), running and to come, at ``SCHED_FIFO``
    ``priority`` (0: leave them as they are). Returns a sentence for the log; never raises:
    the process runs without it."""
    global _granted
    if priority == 0:
        return "real-time priority off (realtime_priority 0); threads at the default policy"
    why = priority_error(priority)
    if why is not None:
        return f"no real-time priority: {why}"
    refused = _probe(priority)
    if refused is not None:
        return refused
    with _lock:
        _granted = priority
        for tid in list(_periodic_threads):
            _set_fifo(tid, priority)
        count = len(_periodic_threads)
    return (f"real-time priority SCHED_FIFO {priority} for the periodic threads ({count} now, "
            "and those that start later); the others at the default policy")


def _probe(priority: int) -> str | None:
    """Whether ``priority`` may be had (None) or why not, tried on a thread of its own that
    ends at once, so that no thread of the process has to be put back."""
    why: list[str] = []

    def attempt() -> None:
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(priority))
        except PermissionError:
            why.append(f"no real-time priority: SCHED_FIFO {priority} needs root, CAP_SYS_NICE "
                       f"or an rtprio limit ≥ {priority} (ulimit -r is {_rtprio_limit()}); "
                       "the threads keep the default policy")
        except OSError as exc:
            why.append(f"no real-time priority: {exc}")

    probe = threading.Thread(target=attempt, name="realtime-probe")
    probe.start()
    probe.join()
    return why[0] if why else None


def _set_fifo(tid: int, priority: int) -> None:
    try:
        os.sched_setscheduler(tid, os.SCHED_FIFO, os.sched_param(priority))
    except OSError:
        pass        # the thread ended meanwhile, or the permission was taken away


def _rtprio_limit() -> str:
    soft, _ = resource.getrlimit(resource.RLIMIT_RTPRIO)
    return "unlimited" if soft == resource.RLIM_INFINITY else str(soft)
