"""The jog watchdog's thread wakes for the first call of a jog, not for every call: a teleop
that streams twists at 125 Hz costs no thread wake-up per twist, and the stop still lands
``timeout`` after the last call (never earlier)."""
import threading
import time

from jaka_driver.backend.clock import WallClock
from jaka_driver.driver.watchdogs import JogWatchdog


class CountingClock(WallClock):
    """Wall time; counts how often the watchdog's thread went back to waiting."""

    def __init__(self):
        self.waits = 0

    def wait(self, event, timeout):
        self.waits += 1
        return super().wait(event, timeout)


def test_fifty_calls_wake_the_watchdog_thread_for_the_first_only():
    clock = CountingClock()
    stopped = threading.Event()
    stopped_at = []
    watchdog = JogWatchdog(lambda: (stopped_at.append(time.monotonic()), stopped.set()),
                           timeout=1.0, clock=clock)
    try:
        time.sleep(0.05)                 # the thread waits for a first call
        idle_waits = clock.waits
        for _ in range(50):              # 0.5 s of calls, 10 ms apart: within one timeout
            last = time.monotonic()
            watchdog.kick(1, -1, 0.05)
            time.sleep(0.01)
        calls_waits = clock.waits - idle_waits
        assert stopped.wait(5.0)
        # woken by the first call (1), then at the first deadline it saw it found the later
        # one (1 more); a wake-up per call would be 50
        assert calls_waits <= 2, calls_waits
        assert stopped_at[0] - last >= 1.0 - 1e-3      # never before timeout after the last
        assert watchdog.session is None
    finally:
        watchdog.close()
