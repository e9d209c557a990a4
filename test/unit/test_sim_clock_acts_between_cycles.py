"""The twin's simulated clock lets requests and woken waiters act only between cycles.

The test plays the physics loop itself (``wait_for_cycle`` … ``tick``) and holds a cycle
"in progress" for far longer than the clock's wall-time slices, so each rule is checked
without depending on how the threads happen to be scheduled:

* an event set inside a cycle (a move's completion) wakes its holding waiter when that cycle
  has ticked, not while it is being stepped — else what the waiter does next (plan from the
  latest sample, read the time) depends on how far the cycle had got;
* a request (``hold``) that arrives while a cycle is being stepped starts after it — also
  when the loop steps its cycles back to back (factor 0);
* a request that arrives while the pacer waits for the wall clock stops the cycle from
  starting;
* a paused clock's steps stop for a request (or a watchdog acting) as running time does; only
  the thread that asked for the steps lets them run while it waits for them. (Steps that ran
  through every hold let a jog's watchdog stop the arm as many cycles late as its thread
  waited for the CPU: 25 on a busy machine.)
"""
import threading
import time

from jaka_driver.backend.clock import SimClock

CYCLE = 0.008
IN_CYCLE_S = 0.3          # wall time a cycle stays "being stepped": 6 wall slices


def _in_thread(fn) -> threading.Thread:
    thread = threading.Thread(target=fn, daemon=True)
    thread.start()
    return thread


def _acts_only_after_the_tick(clock: SimClock, thread: threading.Thread, acted_at: list,
                              what: str) -> None:
    """With a cycle started, ``thread`` has not acted ``IN_CYCLE_S`` later; after the tick it
    acts, at cycle 1."""
    time.sleep(IN_CYCLE_S)
    assert acted_at == [], what
    clock.tick()
    thread.join(2.0)
    assert acted_at == [1]


def test_an_event_set_inside_a_cycle_wakes_its_waiter_after_the_tick():
    clock, event, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event(), threading.Event()
    woke_at = []

    def waiter():
        with clock.hold():
            clock.wait(event, 10.0)
            woke_at.append(clock.cycles)

    thread = _in_thread(waiter)
    time.sleep(0.1)                          # the waiter waits: time may run
    assert clock.wait_for_cycle(quit_)       # a cycle starts...
    event.set()                              # ...and the move completes inside it
    _acts_only_after_the_tick(clock, thread, woke_at,
                              "the waiter woke while the cycle was still being stepped")


def test_a_request_arriving_during_a_cycle_starts_after_it():
    clock, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event()
    started_at = []

    def request():
        with clock.hold():
            started_at.append(clock.cycles)

    assert clock.wait_for_cycle(quit_)
    _acts_only_after_the_tick(clock, _in_thread(request), started_at,
                              "the request started inside the cycle")


def test_a_request_to_a_twin_stepping_back_to_back_starts_after_the_cycle_in_progress():
    """At factor 0 the physics loop starts its next cycle right after each tick: a request
    that only waited for "no cycle being stepped" lost that race every time (and waited out
    the clock's STEPPING_WAIT, 1 s, while ~a thousand cycles ran)."""
    clock, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event()

    def physics():
        while clock.wait_for_cycle(quit_):
            time.sleep(0.0005)               # stepping the cycle
            clock.tick()

    thread = _in_thread(physics)
    try:
        for _ in range(20):
            before = clock.cycles
            with clock.hold(react=False):
                assert clock.cycles - before <= 1, clock.cycles - before
            time.sleep(0.01)                 # time runs between the requests
    finally:
        quit_.set()
        thread.join(2.0)


def test_a_request_during_the_pacers_wait_stops_the_cycle():
    cycle = 0.5                              # paced at real time: the pacer waits ~0.5 s
    clock, quit_ = SimClock(cycle, real_time_factor=1.0), threading.Event()
    started = threading.Event()
    _in_thread(lambda: clock.wait_for_cycle(quit_) and started.set())
    time.sleep(0.1)                          # the pacer is waiting for the wall clock
    with clock.hold():
        assert not started.wait(1.0), "the cycle started while a request held time"
    assert started.wait(2.0)
    quit_.set()


def test_a_request_stops_a_paused_clocks_steps_but_the_step_request_does_not():
    clock, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event()
    clock.pause()
    holding, release, started = threading.Event(), threading.Event(), threading.Event()
    stepped = []

    def request():
        with clock.hold(react=False):
            holding.set()
            release.wait(10.0)

    def step_request():                      # as the node's ~sim/step: a request itself
        with clock.hold():
            stepped.append(clock.step(2, 10.0))

    _in_thread(request)
    assert holding.wait(2.0)
    step = _in_thread(step_request)
    _in_thread(lambda: clock.wait_for_cycle(quit_) and started.set())
    assert not started.wait(IN_CYCLE_S), "a step ran while a request held time"
    release.set()
    assert started.wait(2.0), "the step request's own hold stopped its steps"
    clock.tick()
    assert clock.wait_for_cycle(quit_)
    clock.tick()
    step.join(2.0)
    assert stepped == [True] and clock.cycles == 2


def test_a_holder_whose_event_is_set_stops_time_until_it_has_run():
    """As the jog watchdog kicked between two steps: its event set, the next cycle waits for
    the waiter to run (it may still hold time when it does), however late its thread gets a
    core — not only until its next look at the clock."""
    clock, event, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event(), threading.Event()
    order = []

    def watchdog():
        with clock.hold(react=False):
            clock.wait(event, 10.0)
            order.append("acted")
            time.sleep(0.05)                 # still holding time while it acts

    thread = _in_thread(watchdog)
    time.sleep(0.1)                          # it waits on the clock: time may run
    event.set()
    assert clock.wait_for_cycle(quit_)       # the next cycle starts only once it has acted
    order.append("cycle")
    clock.tick()
    thread.join(2.0)
    assert order == ["acted", "cycle"]


def test_a_step_is_answered_once_what_its_last_cycle_woke_has_acted():
    """As a program's ``wait`` ending at the last stepped cycle: its next step acts before the
    step is answered, so a request sent after the step comes after it on any machine load."""
    clock, quit_ = SimClock(CYCLE, real_time_factor=0), threading.Event()
    clock.pause()
    order = []

    def program():
        with clock.hold(react=False):
            clock.sleep(2 * CYCLE)
            time.sleep(IN_CYCLE_S)           # its next step takes a while (wall time)
            order.append(("program acted", clock.cycles))

    def physics():
        while clock.wait_for_cycle(quit_):
            clock.tick()

    waiting = _in_thread(program)
    time.sleep(0.1)                          # it waits on the clock
    _in_thread(physics)
    try:
        assert clock.step(2, 5.0)
        order.append(("step answered", clock.cycles))
        waiting.join(2.0)
        assert order == [("program acted", 2), ("step answered", 2)]
    finally:
        quit_.set()
