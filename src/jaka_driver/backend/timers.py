"""Timers: callbacks scheduled on a clock (jaka_driver.backend.clock), run by a thread that
acts at their time instead of a thread per timer that waits for it.

:class:`Timer` is one scheduled callback (cancel it before it runs); :func:`run_timer` runs
one, logging a failure instead of raising it (a timer's failure must not stop the thread that
runs the others: in sim time the physics loop); :class:`TimerThread` is the wall clock's
runner, one thread started with the first timer. The sim clock keeps its own heap of timers,
due at cycle counts, and runs them from ``SimClock.tick``.
"""
from __future__ import annotations

import heapq
import itertools
import logging
import threading
import time
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..host import realtime

log = logging.getLogger(__name__)


@dataclass(order=True)
class Timer:
    """A callback scheduled on a clock (:meth:`SimClock.call_at`, :meth:`WallClock.call_at`):
    ``due`` is when it acts (a cycle count on the sim clock, monotonic s on the wall clock)."""

    due: float
    seq: int
    callback: Callable[[], object] = field(compare=False)
    cancelled: bool = field(default=False, compare=False)

    def cancel(self) -> None:
        """It will not run (if it has not yet)."""
        self.cancelled = True


def run_timer(timer: Timer) -> None:
    """Run ``timer`` unless cancelled; a failure is logged."""
    if timer.cancelled:
        return
    try:
        timer.callback()
    except Exception:  # noqa: BLE001 — a timer's failure must not stop time or other timers
        log.exception("timer %r failed", getattr(timer.callback, "__qualname__", timer.callback))


class TimerThread:
    """Runs timers due in wall time (``time.monotonic``, s) on one thread, started with the
    first, in time order."""

    def __init__(self):
        self._timers: list[Timer] = []
        self._seq = itertools.count()
        self._cond = threading.Condition()
        self._thread: Optional[threading.Thread] = None

    def call_at(self, t: float, callback: Callable[[], object]) -> Timer:
        timer = Timer(t, next(self._seq), callback)
        with self._cond:
            heapq.heappush(self._timers, timer)
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="clock-timers",
                                                daemon=True)
                self._thread.start()
            self._cond.notify()
        return timer

    @realtime.runs_periodically      # a watchdog's stop is due on time, as the cycle's work
    def _run(self) -> None:
        while True:
            with self._cond:
                while True:
                    while self._timers and self._timers[0].cancelled:
                        heapq.heappop(self._timers)
                    wait = (self._timers[0].due - time.monotonic()) if self._timers else None
                    if wait is not None and wait <= 0:
                        timer = heapq.heappop(self._timers)
                        break
                    self._cond.wait(wait)
            run_timer(timer)
