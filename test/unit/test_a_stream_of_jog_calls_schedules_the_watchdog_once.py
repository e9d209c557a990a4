"""The jog watchdog is a timer on the clock, scheduled by the first call of a jog, not by
every call: a teleop that streams twists at 125 Hz costs nothing per twist, and the stop still
lands ``timeout`` after the last call (never earlier) — in sim time at exactly the cycle the
calls decide, however late any thread runs."""
import threading
import time

from jaka_driver.backend.clock import SimClock, WallClock
from jaka_driver.driver.watchdogs import JogWatchdog

CYCLE = 0.008


class CountingClock(WallClock):
    """Wall time; counts the timers scheduled on it."""

    def __init__(self):
        super().__init__()
        self.scheduled = 0

    def call_at(self, t, callback):
        self.scheduled += 1
        return super().call_at(t, callback)


def test_fifty_calls_schedule_the_watchdog_for_the_first_and_its_last_deadline_only():
    clock = CountingClock()
    stopped = threading.Event()
    stopped_at = []
    watchdog = JogWatchdog(lambda: (stopped_at.append(time.monotonic()), stopped.set()),
                           timeout=1.0, clock=clock)
    try:
        for _ in range(50):              # 0.5 s of calls, 10 ms apart: within one timeout
            last = time.monotonic()
            watchdog.kick(1, -1, 0.05)
            time.sleep(0.01)
        assert clock.scheduled == 1, clock.scheduled
        assert stopped.wait(5.0)
        # the first call's timer (1) found the later deadline and scheduled it (1 more)
        assert clock.scheduled == 2, clock.scheduled
        # Wall clock: this checks WallClock's timer thread (the sim clock's case is below).
        # time.monotonic on both sides (µs); 1 ms below the timeout for the float sum of the
        # deadline, no bound above (a late stop is load, an early one a bug).
        assert stopped_at[0] - last >= 1.0 - 1e-3      # never before timeout after the last
        assert watchdog.session is None
    finally:
        watchdog.close()


def run_cycles(clock: SimClock, n: int) -> None:
    """Play the physics loop for ``n`` cycles (no physics: the clock's side of it)."""
    quit_ = threading.Event()
    for _ in range(n):
        assert clock.wait_for_cycle(quit_)
        clock.tick()


def test_in_sim_time_the_stop_lands_in_the_cycle_the_last_call_decides():
    clock = SimClock(CYCLE, real_time_factor=0)
    stops = []
    watchdog = JogWatchdog(lambda: stops.append(clock.cycles), timeout=0.1, clock=clock)
    run_cycles(clock, 3)
    watchdog.kick(0, 0, 0.1)             # at cycle 3: due at 3 + 12.5 → the end of cycle 16
    run_cycles(clock, 5)
    watchdog.kick(0, 0, 0.1)             # at cycle 8: due at the end of cycle 21 (8 + 12.5)
    run_cycles(clock, 12)
    assert stops == [] and watchdog.session is not None
    run_cycles(clock, 1)
    assert stops == [21] and watchdog.session is None
    run_cycles(clock, 20)
    assert stops == [21]


def test_a_cleared_jog_is_not_stopped_and_a_new_one_gets_its_own_deadline():
    clock = SimClock(CYCLE, real_time_factor=0)
    stops = []
    watchdog = JogWatchdog(lambda: stops.append(clock.cycles), timeout=0.04, clock=clock)
    watchdog.kick(0, 0, 0.1)
    run_cycles(clock, 2)
    watchdog.clear()
    run_cycles(clock, 10)
    assert stops == []
    watchdog.kick(0, 0, 0.1)             # at cycle 12: 5 cycles
    run_cycles(clock, 5)
    assert stops == [17]
