"""A servo target takes effect in the cycle after the one it arrived in, by the cycles' nominal
times (the samples' stamps), also when it arrives in the fraction of a millisecond between a
cycle's nominal start and the moment the physics thread wakes to choose that cycle's setpoint
(its wake-up margin, 0.2 ms, plus however late it is). Before, such a target joined the cycle
it arrived in: a client saw it reached one cycle early, in the sample that ends its own cycle.

The real zu5 twin on its real-time thread; targets sent 50 µs after a nominal cycle start.
The cycles' nominal times are the measurement: a trial in which the physics loop stalled for
more than STALL_CYCLES and skipped ahead (its ``overruns`` count grew), or whose samples a slow
reader found already out of the loop's history, or whose call returned only after the cycle it
was sent in had ended (seen once in a clean-clone run: the target then counted from a cycle
later than its send), measured nothing and is sent again; every
trial that measured must pass, and trials go on until twelve measured and six sends fell in the
window before the wake-up (at most 120 trials: on a busy machine the sending thread is late for
some).
"""
import time

import numpy as np

from jaka_driver.common.models import load_model
from jaka_driver.sim import SimBackend
from support.ros_harness import wait_until

STEP_RAD = 0.0005       # every joint, from rest: reached within one cycle (~0.06 rad/s)
AFTER_START_S = 50e-6
EARLY_SENDS = 6         # sends that must fall before the physics thread wakes
MEASURED = 12           # trials that measured, at least
MAX_TRIALS = 120


def _samples_at(physics, stamps):
    """The samples stamped ``stamps`` (s), or None if the loop's history no longer has one."""
    found = {round(s.stamp / 1e-4): s for s in physics.samples_since(min(stamps) - 1e-4)}
    picked = [found.get(round(t / 1e-4)) for t in stamps]
    return None if any(s is None for s in picked) else picked


def test_a_target_sent_just_after_a_cycle_starts_waits_for_the_next_cycle():
    twin = SimBackend(load_model("zu5"))
    twin.start()
    try:
        assert twin.servo_enable(True).ok
        physics, cycle = twin._physics, twin._physics.cycle
        time.sleep(0.1)
        q = physics.servo.setpoint.copy()     # where the drives hold the arm
        early_window = measured = trial = 0
        while early_window < EARLY_SENDS or measured < MEASURED:
            assert trial < MAX_TRIALS, f"{early_window} of {measured} measured sends fell " \
                f"before the wake-up in {trial} trials"
            q = q + (STEP_RAD if trial % 2 == 0 else -STEP_RAD)
            trial += 1
            overruns = physics.overruns
            last = physics.sample().stamp                   # a cycle's nominal end
            start = last + 2 * cycle                        # a cycle start still ahead
            while time.time() < start + AFTER_START_S:      # spin: sleep is too coarse
                pass
            sent = time.time()
            assert twin.servo_j(q).ok
            returned = time.time()
            # The cycle it arrived in ends at the first stamp at or after the send.
            arrival_end = last + np.ceil((sent - last) / cycle - 1e-9) * cycle
            if returned >= arrival_end:
                # the call itself outlasted that cycle (its thread lost the core): the target
                # arrived somewhere in [sent, returned], in that cycle or a later one
                continue
            assert wait_until(lambda: physics.sample().stamp >= arrival_end + 3 * cycle, 5.0)
            samples = _samples_at(physics, [arrival_end - cycle, arrival_end,
                                            arrival_end + cycle])
            if samples is None or physics.overruns != overruns:
                continue                                    # measured nothing: again
            before, own, next_ = (s.q for s in samples)
            measured += 1
            early_window += sent - start < 0.15e-3          # before the physics wakes
            assert np.max(np.abs(own - before)) < 0.1 * STEP_RAD, (
                f"trial {trial}: sent {1e3 * (sent - start):.3f} ms into a cycle, the target "
                "was already reached at that cycle's end")
            moved = np.abs(next_ - before)
            assert np.all(moved > 0.5 * STEP_RAD), f"trial {trial}: not reached a cycle later"
    finally:
        twin.shutdown()
