"""Timers on the twin's simulated clock run in the thread that advances time, at the end of
the cycle their time falls in, before anything else may act between that cycle and the next:
a request arriving meanwhile starts after them, a holding waiter due at the same cycle wakes
after them. A callback that would wait for a cycle (its own thread makes them) is refused."""
import threading
import time

import pytest

from jaka_driver.backend.clock import SimClock, WallClock

CYCLE = 0.008


def _cycle(clock: SimClock, quit_=threading.Event()) -> None:
    assert clock.wait_for_cycle(quit_)
    clock.tick()


def test_a_timer_runs_when_the_cycle_its_time_falls_in_has_ticked():
    clock = SimClock(CYCLE, real_time_factor=0)
    ran = []
    clock.call_at(0.020, lambda: ran.append(clock.cycles))   # 2.5 cycles: the end of cycle 3
    clock.call_at(0.016, lambda: ran.append(("exact", clock.cycles)))
    cancelled = clock.call_at(0.008, lambda: ran.append("cancelled"))
    cancelled.cancel()
    for _ in range(5):
        _cycle(clock)
    assert ran == [("exact", 2), 3]


def test_a_timer_for_now_or_the_past_runs_at_the_end_of_the_next_cycle():
    clock = SimClock(CYCLE, real_time_factor=0)
    _cycle(clock)
    ran = []
    clock.call_at(0.0, lambda: ran.append(clock.cycles))
    clock.call_at(clock.now(), lambda: ran.append(clock.cycles))
    _cycle(clock)
    assert ran == [2, 2]


def test_a_request_arriving_while_a_timer_runs_starts_after_it():
    clock, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event()
    order = []
    entered = threading.Event()

    def slow_timer():
        entered.set()
        time.sleep(0.2)
        order.append("timer")

    def request():
        entered.wait(2.0)
        with clock.hold():
            order.append("request")

    clock.call_at(CYCLE, slow_timer)
    thread = threading.Thread(target=request, daemon=True)
    thread.start()
    assert clock.wait_for_cycle(quit_)
    clock.tick()
    thread.join(2.0)
    assert order == ["timer", "request"]


def test_a_timer_may_not_wait_on_or_hold_the_clock_it_runs_in():
    clock = SimClock(CYCLE, real_time_factor=0)
    errors = []

    def waits():
        try:
            clock.sleep(CYCLE)
        except RuntimeError as exc:
            errors.append(str(exc))

    clock.call_at(CYCLE, waits)
    _cycle(clock)
    assert len(errors) == 1 and "timer callback" in errors[0]


def test_wall_clock_timers_run_in_time_order_on_the_timer_thread():
    clock = WallClock()
    ran, done = [], threading.Event()
    now = clock.now()
    clock.call_at(now + 0.06, lambda: (ran.append("b"), done.set()))
    clock.call_at(now + 0.02, lambda: ran.append("a"))
    clock.call_at(now + 0.04, lambda: ran.append("x")).cancel()
    assert done.wait(2.0)
    assert ran == ["a", "b"]
