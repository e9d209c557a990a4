"""The driver's watchdogs, kept by RobotDriver whatever the backend: the jog keep-alive and the
servo stream.

A jog runs only while its client keeps calling: 3.0 s after the last call it is stopped
(docs/interface.md, "jog"). A servo stream that stops leaves the arm holding its last target,
and the next servo call is told how long the stream had stopped.

Both keep time on the backend's clock (:mod:`jaka_driver.backend.clock`): wall time, or the
twin's sim time, in which the jog stops exactly ``timeout`` after the cycle of its last call
(a timer on the clock, run by the physics thread at that cycle's end: no thread has to wake
up in time).
"""
from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Callable, Optional

from ..backend.clock import SimClock, WallClock
from ..backend.timers import Timer


@dataclass
class JogSession:
    """The jog being kept alive: what moves and when the client last asked for it."""

    coord: int
    index: int
    speed: float
    last_call: float


class JogWatchdog:
    """Stops a jog ``timeout`` seconds (of ``clock``) after its last call.

    No thread waits for the deadline: it is a timer on the clock (:meth:`SimClock.call_at`).
    In sim time ``stop`` runs in the physics thread at the end of the cycle the deadline falls
    in, before anything else acts and before the next cycle starts, so it lands in the cycle
    the calls alone decide on any machine load; on the wall clock it runs on the clock's timer
    thread. ``stop`` must be thread-safe, quick, and never wait for a cycle (it may post to
    the motion slot, as ``backend.jog_stop`` does).
    """

    #: s: a deadline this close to now counts as reached (sim time: a cycle's end lands on
    #: ``last_call + timeout`` up to rounding)
    EPSILON = 1e-9

    def __init__(self, stop: Callable[[], object], timeout: float = 3.0, *,
                 clock: WallClock | SimClock):
        self._stop = stop
        self.timeout = timeout
        self._clock = clock
        self._lock = threading.Lock()
        self._session: Optional[JogSession] = None
        self._timer: Optional[Timer] = None      # the deadline scheduled on the clock
        self._closed = False

    @property
    def session(self) -> Optional[JogSession]:
        with self._lock:
            return self._session

    def kick(self, coord: int, index: int, speed: float) -> Optional[JogSession]:
        """Record a jog call; returns the session it replaces (None if none was running).

        Only the first call of a jog schedules a timer: while a session runs, the timer fires
        at the last deadline it saw and then schedules the later one itself, so a stream of
        calls (a teleop's twists at 125 Hz) costs nothing per call — the stop still lands
        ``timeout`` after the last call."""
        with self._lock:
            previous = self._session
            self._session = JogSession(coord, index, speed, self._clock.now())
            if self._timer is None and not self._closed:
                self._timer = self._clock.call_at(self._session.last_call + self.timeout,
                                                  self._due)
        return previous

    def clear(self) -> Optional[JogSession]:
        """Forget the session without stopping (the caller stops the arm itself)."""
        with self._lock:
            previous, self._session = self._session, None
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None
        return previous

    def close(self) -> None:
        with self._lock:
            self._closed = True
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None

    def _due(self) -> None:
        """The timer: stop the jog if its last call is ``timeout`` old, else wait for the
        later deadline a call has set meanwhile."""
        with self._lock:
            self._timer = None
            session = self._session
            if session is None or self._closed:
                return
            deadline = session.last_call + self.timeout
            if deadline - self._clock.now() > self.EPSILON:
                self._timer = self._clock.call_at(deadline, self._due)
                return
            self._session = None
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
