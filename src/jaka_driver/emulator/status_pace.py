"""When the emulator's status packet goes out (port 10000): right after the end of the twin's
cycle it shows, as a controller sends the state of its own control cycle once per cycle.

A packet pushed on a timer of its own shows whichever cycle ended last, at a phase to the
twin's cycles that is the luck of the start: a client that stamps the packets at receipt and
times its commands by those stamps (half a cycle after a cycle's end, say) can then land at a
cycle's very end, and every command it sends counts one cycle later than it means. So the
broadcaster waits for the twin's cycles (the backend contract's ``wait_for_sample``, woken the
moment a cycle's sample exists) and a packet follows its cycle by the time the broadcaster
takes to wake, never by up to a period.

* **Which cycles.** The packets are due every ``period`` s of the twin's time (its samples'
  stamps: wall time, or sim time when the twin owns time), each going out after the cycle that
  ends nearest its due time: every cycle at the 8 ms default, every 4th or 3rd cycle
  (32 / 32 / 24 ms …) for 30 ms. A twin in sim time gets its packets at ``period`` of sim time,
  whatever its pace.
* **A period shorter than the cycle.** After each cycle's packet, more follow every ``period`` s
  of wall time until the next cycle ends, each showing the latest cycle.
* **When no cycle ends** (a paused twin, a stalled loop): ``period`` + :data:`LATE` s after the
  last packet the stream goes on at ``period`` s of wall time, each packet showing the latest
  cycle, so that a client's link watch sees a controller that is there; the next cycle that
  ends takes over again.

The pacer only says when; the broadcaster's own thread builds and pushes the packet (never the
twin's physics thread). Without a twin (``arm`` None) the packets go on a wall-clock timer.
"""
from __future__ import annotations

import threading
import time
from typing import Optional, Protocol

from ..common.constants import SERVO_CYCLE

LATE = 2 * SERVO_CYCLE   # s past a due packet's time without a cycle before the wall clock paces
_POLL = 0.1              # s, how often a waiting pacer looks at the stop flag


class CycleSource(Protocol):
    """What the pacer needs of the twin (the backend contract's two methods)."""

    def wait_for_sample(self, after: float, timeout: float) -> bool: ...

    def state(self): ...


class StatusPacer:
    """Says when the next status packet goes out: :meth:`wait`. ``arm``: the twin whose
    cycles the packets follow (None: a wall-clock timer of ``period`` s); ``cycle``: its
    cycle, s. One thread waits on it."""

    def __init__(self, arm: Optional[CycleSource], period: float, cycle: float = SERVO_CYCLE):
        self.arm = arm
        self.period = float(period)
        self.cycle = float(cycle)
        # s of wall time past a cycle's packet that the next may wait for its cycle
        self._late = LATE if self.period >= self.cycle else 0.0
        self._seen = float("-inf")      # stamp of the newest cycle seen
        self._due = float("-inf")       # stamp (the twin's time) the next packet is due at
        self._deadline = time.monotonic() + self.period   # wall time of a packet without cycle
        #: packets that followed their cycle, and those the wall clock paced (no cycle ended)
        self.on_cycle = 0
        self.on_wall_clock = 0

    def wait(self, quit_: threading.Event) -> bool:
        """Block until the next packet is due; False once ``quit_`` is set."""
        if self.arm is None:
            return self._wait_on_wall_clock(quit_)
        arm = self.arm
        while not quit_.is_set():
            left = self._deadline - time.monotonic()
            if left <= 0:
                self._paced_by_wall_clock()
                return True
            if not arm.wait_for_sample(self._seen, min(left, _POLL)):
                continue
            stamp = arm.state().stamp
            self._seen = stamp
            # the cycle that ends nearest the due time: half a cycle early still counts
            if stamp + self.cycle / 2 < self._due:
                continue
            # due times step by the period (the long-run rate is the period's); after a stall
            # they start again from this cycle, without a burst of packets to catch up
            self._due = (self._due + self.period if self._due > stamp - self.period
                         else stamp + self.period)
            self._deadline = time.monotonic() + self.period + self._late
            self.on_cycle += 1
            return True
        return False

    def _paced_by_wall_clock(self) -> None:
        now = time.monotonic()
        self._deadline += self.period
        if self._deadline <= now:         # fell behind (a stall): no burst
            self._deadline = now + self.period
        self.on_wall_clock += 1

    def _wait_on_wall_clock(self, quit_: threading.Event) -> bool:
        while not quit_.is_set():
            left = self._deadline - time.monotonic()
            if left <= 0:
                self._paced_by_wall_clock()
                return True
            quit_.wait(min(left, _POLL))
        return False
