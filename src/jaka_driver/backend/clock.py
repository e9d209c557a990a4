"""A backend's time: the wall clock, or the twin's simulated time.

The driver keeps every timeout on its backend's clock (blocking moves, the jog watchdog, the
servo stream, the trajectory monitor), so the same code runs in wall time against a
controller and in simulated time against a twin that owns time (docs/design.md, "Time").
A timer that acts by itself (a watchdog) is a callback scheduled on the clock
(:meth:`SimClock.call_at`), not a thread that waits: in sim time the thread that advances time
runs it at the boundary of its cycle, so no thread's wake-up decides when it acts.

:class:`WallClock` is ``time.monotonic``. :class:`SimClock` is the twin's time: cycles × 8 ms
since the twin started, advanced by the physics loop only. Its rules (the driver relies on
them for determinism; docs/twin.md "Simulated time" tells users):

- **Pacing.** A cycle may start once the wall clock allows it: ``real_time_factor`` 1 paces
  cycles to the wall clock, 2 twice as fast, 0 as fast as the machine steps.
- **A request stops time.** While a thread is inside :meth:`SimClock.hold` (a service request
  in the driver, the jog watchdog acting), no cycle starts: a command arrives at the sim time
  current when it came in, and takes effect in the cycle after, however long the driver
  needed (in wall time) to check and plan it.
- **Waiting lets time run.** A holding thread that waits on the clock (:meth:`SimClock.wait`,
  :meth:`SimClock.sleep`) stops holding until it is woken; it is woken *between* two cycles
  and holds again from then, so what it does next happens at a definite sim time — also when
  what it waits for (a move's completion) happens inside a cycle: it wakes once that cycle
  has ended.
- **Requests act between cycles.** A request that arrives while a cycle is being stepped
  starts once that cycle has ended, as a controller latches commands between its cycles.
- **A reply waits for its caller.** When a request's reply is made, time stands still until
  the next request arrives (or an in-process caller waits on the clock), at most
  ``REACTION_WINDOW`` s of wall time: a client that calls again at once (a robot program's
  next line) arrives in the same cycle on any machine load.
- **A servo stream paces the twin.** After a cycle in which a servo target arrived, the next
  cycle waits (at most ``REACTION_WINDOW``) for the next target: a client that sends one
  target per /clock tick or per state sample is in step with the twin at any speed.
- **Paused, it steps only when told.** :meth:`SimClock.pause` stops the cycles whatever
  else would let them run; :meth:`SimClock.step` lets exactly N more run, then stands still
  again; :meth:`SimClock.unpause` lets time run on. The steps keep every other rule: a
  request, or a program's step, stops them as it stops running time (the thread that asked
  for the steps lets them run while it waits, as a waiter does), and the step is answered
  once what its last cycle woke has acted: a request after the step comes after that, as
  it would after N cycles at real time.
- **Timers act at their cycle's end.** A callback scheduled with :meth:`SimClock.call_at`
  for sim time ``t`` runs in the physics thread when the first cycle ending at or after ``t``
  has ticked, before anything else may act between that cycle and the next (requests, woken
  waiters) and before the next cycle starts. A step of N cycles runs exactly the timers N
  cycles at real time would. A callback must be quick and must never wait for a cycle (it
  runs in the thread that makes them): posting to the motion slot is fine.
- **A reader is not outrun.** With a consumer registered (the node's state publisher), the
  twin runs at most ``MAX_LAG`` cycles ahead of what it has published.

Nothing may freeze the twin: a hold older than ``HOLD_LIMIT`` s of wall time stops counting.
"""
from __future__ import annotations

import heapq
import itertools
import logging
import math
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Optional

from ..common.constants import STALL_CYCLES
from .timers import Timer, TimerThread, run_timer

log = logging.getLogger(__name__)

REACTION_WINDOW = 0.2     # s wall: how long time waits for a caller's next request
HOLD_LIMIT = 10.0         # s wall: a hold older than this no longer stops time
MAX_LAG = 16              # cycles the twin may run ahead of its consumer
WALL_SLICE = 0.05         # s wall: waiters re-check their condition at least this often
STEPPING_WAIT = 1.0       # s wall: the longest a new request waits for a cycle to end


class WallClock:
    """Wall time (``time.monotonic``, s). Holds and stream marks mean nothing here; timers
    run on one timer thread of the clock's, started with the first."""

    simulated = False

    def __init__(self):
        self._timers = TimerThread()

    def call_at(self, t: float, callback: Callable[[], object]) -> Timer:
        """Run ``callback()`` on the timer thread at wall time ``t`` (s, :meth:`now`'s) or as
        soon after as it gets a core; the callback must be quick (it delays the next)."""
        return self._timers.call_at(t, callback)

    def now(self) -> float:
        return time.monotonic()

    def sleep(self, seconds: float) -> None:
        time.sleep(max(0.0, seconds))

    def wait(self, event: threading.Event, timeout: float) -> bool:
        """Until ``event`` is set or ``timeout`` s pass; True if it is set."""
        return event.wait(max(0.0, timeout))

    @contextmanager
    def hold(self, react: bool = True):
        yield

    def streamed(self) -> None:
        pass


@dataclass
class _Waiter:
    deadline: int                   # cycle count at which the wait times out
    event: Optional[threading.Event]
    woken: bool = False


class SimClock:
    """The twin's time: ``cycles`` × ``cycle`` s. The physics loop calls
    :meth:`wait_for_cycle` before and :meth:`tick` after each cycle; everyone else reads it,
    waits on it, or holds it (see the module docstring)."""

    simulated = True

    def __init__(self, cycle: float, real_time_factor: float = 1.0):
        if not (real_time_factor >= 0 and math.isfinite(real_time_factor)):
            raise ValueError(f"real_time_factor is {real_time_factor}, expected ≥ 0 "
                             "(0 = as fast as possible)")
        self.cycle = cycle
        self.real_time_factor = float(real_time_factor)
        self.cycles = 0
        self._cond = threading.Condition()
        self._holds: dict[int, list] = {}        # thread id -> [depth, wall time since]
        self._waiting: dict[int, _Waiter] = {}
        self._reaction_until = 0.0               # wall time
        self._stream_cycle = -2                  # cycle count when the last servo target came
        self._gap_started = time.monotonic()     # wall time the current gap between cycles began
        self._consumed: Optional[int] = None     # cycles the consumer has taken
        self._anchor: Optional[tuple[float, int]] = None    # (wall time, cycles) of the pacer
        self._stepping = False                   # a cycle has started and not ticked yet
        self._stale_warned = False
        self._paused = False
        self._step_budget = 0                    # cycles a paused clock may still run
        self._timers: list[Timer] = []           # heap, due = cycle count
        self._seq = itertools.count()
        self._timer_thread: Optional[int] = None  # the thread running timers now

    # ---- reading and waiting -------------------------------------------------------------
    def now(self) -> float:
        """Sim time, s since the twin started."""
        return self.cycles * self.cycle

    def _cycles_at(self, t: float) -> int:
        return math.ceil(t / self.cycle - 1e-9)

    def wait(self, event: Optional[threading.Event], timeout: float) -> bool:
        """Until ``event`` is set or ``timeout`` s of sim time pass; True if it is set.
        A thread that holds time lets it run while it waits (module docstring)."""
        tid = threading.get_ident()
        self._not_in_a_timer("wait on")
        with self._cond:
            if event is not None and event.is_set():
                return True
            waiter = _Waiter(self._cycles_at(self.now() + max(0.0, timeout)), event)
            if waiter.deadline <= self.cycles:
                return False
            self._waiting[tid] = waiter
            if tid not in self._holds:
                self._reaction_until = 0.0      # a caller waiting on time has reacted
            self._cond.notify_all()
            try:
                while not waiter.woken:
                    self._cond.wait(WALL_SLICE)
                    # An event set inside a cycle wakes the waiter when the cycle ends (tick),
                    # not while the twin is still finishing it.
                    if event is not None and event.is_set() and not self._stepping:
                        waiter.woken = True
            finally:
                del self._waiting[tid]
                if tid in self._holds:
                    self._holds[tid][1] = time.monotonic()
            return event is not None and event.is_set()

    def sleep(self, seconds: float) -> None:
        self.wait(None, seconds)

    def call_at(self, t: float, callback: Callable[[], object]) -> Timer:
        """Run ``callback()`` in the physics thread once the first cycle ending at or after
        sim time ``t`` (s) has ticked, before the next cycle starts (at the end of the next
        cycle if ``t`` is now or past). Quick, and never waiting for a cycle (module
        docstring)."""
        with self._cond:
            due = max(self._cycles_at(t), self.cycles + 1)
            timer = Timer(due, next(self._seq), callback)
            heapq.heappush(self._timers, timer)
        return timer

    def _not_in_a_timer(self, what: str) -> None:
        if self._timer_thread == threading.get_ident():
            # the thread that would make the cycle waited for is this one: it would never come
            raise RuntimeError(f"a timer callback may not {what} the simulated clock (it runs "
                               "in the thread that advances time)")

    # ---- what stops time -----------------------------------------------------------------
    @contextmanager
    def hold(self, react: bool = True):
        """Time stands still while the calling thread is inside (and not waiting on the
        clock). ``react``: when the outermost hold ends, wait up to REACTION_WINDOW for the
        caller's next request (a reply); False for the servo stream and the watchdog."""
        tid = threading.get_ident()
        self._not_in_a_timer("hold")
        with self._cond:
            self._reaction_until = 0.0          # the request the window waited for is here
            first = tid not in self._holds
            # Held from now, before the wait below: the cycle being stepped ends, and the
            # next one waits for this request. (Waiting first and holding after, a twin at
            # factor 0 started its next cycle in the instant between the tick's notify and
            # this thread's wake-up, every time, and a request waited out STEPPING_WAIT.)
            entry = self._holds.setdefault(tid, [0, time.monotonic()])
            entry[0] += 1
            if first:
                # A cycle being stepped ends first (well under a millisecond; bounded, so a
                # caller that holds what the cycle needs cannot freeze both).
                self._cond.wait_for(lambda: not self._stepping, STEPPING_WAIT)
        try:
            yield
        finally:
            with self._cond:
                entry[0] -= 1
                if entry[0] == 0:
                    del self._holds[tid]
                    if react:
                        self._reaction_until = time.monotonic() + REACTION_WINDOW
                self._cond.notify_all()

    def streamed(self) -> None:
        """A servo target arrived: the cycle after next waits for the next one."""
        with self._cond:
            self._stream_cycle = self.cycles
            self._cond.notify_all()

    def add_consumer(self) -> None:
        """Register the one consumer of samples; from now the twin waits for it."""
        with self._cond:
            self._consumed = self.cycles

    def wait_consumed(self, timeout: float) -> bool:
        """Until the consumer (if any) has taken every sample up to now; False after
        ``timeout`` s of wall time."""
        with self._cond:
            if self._consumed is None:
                return True
            return self._cond.wait_for(lambda: self._consumed >= self.cycles, timeout)

    def consumed(self, t: float) -> None:
        """The consumer has taken the sample of sim time ``t`` (s)."""
        with self._cond:
            self._consumed = max(self._consumed or 0, round(t / self.cycle))
            self._cond.notify_all()

    # ---- pause and step (the twin's own time, backend.twin) ----------------------------------
    @property
    def paused(self) -> bool:
        return self._paused

    def pause(self) -> None:
        """No cycle starts until :meth:`unpause` (or one of :meth:`step`'s); a cycle being
        stepped ends first, so that time stands still from the answer on."""
        with self._cond:
            self._paused, self._step_budget = True, 0
            self._cond.wait_for(lambda: not self._stepping, STEPPING_WAIT)
            self._cond.notify_all()

    def unpause(self) -> None:
        with self._cond:
            self._paused, self._step_budget = False, 0
            self._cond.notify_all()

    def step(self, cycles: int, timeout: float) -> bool:
        """While paused: let ``cycles`` cycles run and wait (at most ``timeout`` s of wall
        time) until they have; True if they have. A caller that holds time (the step request)
        lets the steps run while it waits, as :meth:`wait` does; every other hold stops them."""
        tid = threading.get_ident()
        with self._cond:
            target = self.cycles + cycles
            self._step_budget += cycles
            self._waiting[tid] = _Waiter(target, None)
            self._cond.notify_all()
            try:
                # done once the cycles have run and whatever they woke (a program's next step,
                # a blocking move's return) has acted: a request after the steps comes after
                # those, as it would after N cycles at real time
                return self._cond.wait_for(
                    lambda: (self.cycles >= target
                             and self._awake_holder(time.monotonic(), but=tid) is None),
                    timeout)
            finally:
                del self._waiting[tid]
                if tid in self._holds:
                    self._holds[tid][1] = time.monotonic()

    def _blocked(self, wall: float) -> Optional[float]:
        """None if the next cycle may start now, else the wall time to look again."""
        again = wall + WALL_SLICE
        if self._paused and self._step_budget <= 0:
            return again
        until = self._awake_holder(wall)
        if until is not None:
            return min(again, until)
        if wall < self._reaction_until:
            return self._reaction_until
        if self._stream_cycle == self.cycles - 1 and wall < self._gap_started + REACTION_WINDOW:
            return self._gap_started + REACTION_WINDOW
        if self._consumed is not None and self.cycles - self._consumed >= MAX_LAG:
            return again
        return None

    def _awake_holder(self, wall: float, but: Optional[int] = None) -> Optional[float]:
        """The wall time at which the hold of a thread (other than ``but``) that holds time
        and is not waiting on the clock stops counting, None if there is no such thread."""
        for tid, entry in self._holds.items():
            if tid == but:
                continue
            depth, since = entry
            waiter = self._waiting.get(tid)
            # a holder whose event is set is as good as awake: time stops at this cycle's
            # end until it has run (the jog watchdog kicked while stepping, on a busy machine,
            # woke 0.15 s of sim time late when the cycles ran on until its thread got a core)
            awake = waiter is None or waiter.woken
            if (not awake and waiter.event is not None and waiter.event.is_set()):
                awake = True
                if not self._stepping:           # (inside a cycle it wakes at the tick)
                    waiter.woken = True
                    entry[1] = since = wall      # its hold counts from its wake-up on
            if depth > 0 and awake:
                if wall - since < HOLD_LIMIT:
                    return since + HOLD_LIMIT
                if not self._stale_warned:
                    self._stale_warned = True
                    log.warning("a request has held simulated time for %.0f s of wall time; "
                                "time runs on", HOLD_LIMIT)
        return None

    # ---- the physics loop's side ------------------------------------------------------------
    def wait_for_cycle(self, quit_: threading.Event) -> bool:
        """Block until the next cycle may start (nothing holds time, the pacer allows it)
        and mark it started (until :meth:`tick`); False if ``quit_`` was set meanwhile.
        Whether anything holds time is decided in the same critical section that starts the
        cycle: a request that came during the pacer's wait stops it."""
        held = False
        while True:
            with self._cond:
                while not quit_.is_set():
                    wall = time.monotonic()
                    until = self._blocked(wall)
                    if until is None:
                        break
                    held = True
                    self._cond.wait(max(0.0, min(until, wall + WALL_SLICE) - wall))
                else:
                    return False
                delay = self._pacing_delay(held)
                if delay <= 0:
                    self._stepping = True
                    return True
                held = False
            if quit_.wait(delay):
                return False

    def _pacing_delay(self, held: bool) -> float:
        """Wall seconds until the coming cycle may start at the real-time factor (0 or less:
        now)."""
        if self.real_time_factor <= 0:
            return 0.0
        period = self.cycle / self.real_time_factor
        wall = time.monotonic()
        if (held or self._anchor is None
                or wall - self._due(period) > STALL_CYCLES * period):
            # Time stood still (or the machine stalled): pace on from here; the held
            # time is not caught up in a burst.
            self._anchor = (wall, self.cycles)
        return self._due(period) - wall

    def _due(self, period: float) -> float:
        """Wall time at which the coming cycle has elapsed at the real-time factor."""
        wall0, cycles0 = self._anchor
        return wall0 + (self.cycles + 1 - cycles0) * period

    def tick(self) -> None:
        """A cycle was stepped: time advances by one cycle; the timers due now run (in the
        calling thread, while the cycle still counts as being stepped: nothing else acts
        between the two cycles before them); then the waiters due now are woken (and hold
        again, if they held, before the next cycle may start)."""
        with self._cond:
            self.cycles += 1
            if self._paused and self._step_budget > 0:
                self._step_budget -= 1
            due = []
            while self._timers and self._timers[0].due <= self.cycles:
                due.append(heapq.heappop(self._timers))
        if due:
            self._timer_thread = threading.get_ident()
            try:
                for timer in due:
                    run_timer(timer)
            finally:
                self._timer_thread = None
        with self._cond:
            self._stepping = False
            wall = self._gap_started = time.monotonic()
            for tid, waiter in self._waiting.items():
                if waiter.deadline <= self.cycles or (waiter.event is not None
                                                      and waiter.event.is_set()):
                    waiter.woken = True
                    if tid in self._holds:
                        # a holder's hold counts from its wake-up, not from when it began
                        # to wait: a 3 s wait that took 10 s of wall time on a loaded
                        # machine no longer let the cycles run on while its thread woke
                        self._holds[tid][1] = wall
            self._cond.notify_all()


def make_clock(sim_time: bool, cycle: float, real_time_factor: float = 1.0):
    """The twin's clock: simulated (``sim_time``) or the wall clock."""
    return SimClock(cycle, real_time_factor) if sim_time else WallClock()
