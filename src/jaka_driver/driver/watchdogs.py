"""The driver's watchdogs, kept by RobotDriver whatever the backend: the jog keep-alive and the
servo stream.

A jog runs only while its client keeps calling: 3.0 s after the last call it is stopped
(docs/interface.md, "jog"). A servo stream that stops leaves the arm holding its last target,
and the next servo call is told how long the stream had stopped.

Both keep time on the backend's clock (:mod:`jaka_driver.backend.clock`): wall time, or the
twin's sim time, in which the jog stops exactly ``timeout`` after the cycle of its last call.
"""
from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Callable, Optional

from ..backend.clock import SimClock, WallClock
from ..host import realtime


@dataclass
class JogSession:
    """The jog being kept alive: what moves and when the client last asked for it."""

    coord: int
    index: int
    speed: float
    last_call: float


class JogWatchdog:
    """Stops a jog ``timeout`` seconds (of ``clock``) after its last call.

    ``stop`` is called from the watchdog's own thread; it must be thread-safe. The thread
    holds simulated time while it acts, so the stop lands in a definite cycle.
    """

    def __init__(self, stop: Callable[[], object], timeout: float = 3.0, *,
                 clock: WallClock | SimClock):
        self._stop = stop
        self.timeout = timeout
        self._clock = clock
        self._lock = threading.Lock()
        self._session: Optional[JogSession] = None
        self._changed = threading.Event()       # a kick, a clear or close: look again
        self._quit = False
        self._thread = threading.Thread(target=self._run, name="jog-watchdog", daemon=True)
        self._thread.start()

    @property
    def session(self) -> Optional[JogSession]:
        with self._lock:
            return self._session

    def kick(self, coord: int, index: int, speed: float) -> Optional[JogSession]:
        """Record a jog call; returns the session it replaces (None if none was running).

        Only the first call of a jog wakes the watchdog's thread: while a session runs, the
        thread sleeps until the last deadline it saw and then finds the later one itself, so a
        stream of calls (a teleop's twists at 125 Hz) costs no thread wake-up per call — the
        stop still lands ``timeout`` after the last call."""
        with self._lock:
            previous = self._session
            self._session = JogSession(coord, index, speed, self._clock.now())
        if previous is None:
            self._changed.set()
        return previous

    def clear(self) -> Optional[JogSession]:
        """Forget the session without stopping (the caller stops the arm itself)."""
        with self._lock:
            previous, self._session = self._session, None
        self._changed.set()
        return previous

    def close(self) -> None:
        self._quit = True
        self._changed.set()
        self._thread.join(timeout=1.0)

    @realtime.runs_periodically
    def _run(self) -> None:
        clock = self._clock
        with clock.hold(react=False):
            while True:
                self._changed.clear()
                if self._quit:
                    return
                session = self.session
                if session is None:
                    clock.wait(self._changed, 3600.0)
                    continue
                remaining = session.last_call + self.timeout - clock.now()
                if remaining > 0:
                    clock.wait(self._changed, remaining)
                    continue
                with self._lock:
                    expired = self._session is session
                    if expired:
                        self._session = None
                if expired:
                    self._stop()


class ServoStream:
    """Tracks the servo target stream: the last target and when it came.

    The reference for the over-speed check of the next target is the last target while the
    stream is alive, else the measured joints (after a pause the arm is where it held).
    """

    def __init__(self, timeout: float = 0.1, *, clock: WallClock | SimClock):
        self.timeout = timeout
        self._clock = clock
        self._lock = threading.Lock()
        self._last_target = None
        self._last_time: Optional[float] = None

    def reset(self) -> None:
        with self._lock:
            self._last_target, self._last_time = None, None

    def reference(self, measured):
        """(reference joints for the next step, seconds the stream had stopped or None)."""
        with self._lock:
            if self._last_time is None:
                return measured, None
            gap = self._clock.now() - self._last_time
            if gap > self.timeout:
                return measured, gap
            return self._last_target, None

    def accepted(self, target) -> None:
        with self._lock:
            self._last_target, self._last_time = target, self._clock.now()
