"""A servo target takes effect in the cycle after the one it arrived in, by the cycles' nominal
times (the samples' stamps), also when it arrives in the fraction of a millisecond between a
cycle's nominal start and the moment the physics thread wakes to choose that cycle's setpoint
(its wake-up margin, 0.2 ms, plus however late it is). Before, such a target joined the cycle
it arrived in: a client saw it reached one cycle early, in the sample that ends its own cycle.

The real zu5 twin on its real-time thread; targets sent 50 µs after a nominal cycle start.
"""
import time

import numpy as np

from jaka_driver.common.models import load_model
from jaka_driver.sim import SimBackend

STEP_RAD = 0.0005       # every joint, from rest: reached within one cycle (~0.06 rad/s)
AFTER_START_S = 50e-6


def _sample_at(physics, stamp: float):
    for s in physics.samples_since(stamp - 1e-4):
        if abs(s.stamp - stamp) < 1e-4:
            return s
    raise AssertionError(f"no sample stamped {stamp:.4f}")


def test_a_target_sent_just_after_a_cycle_starts_waits_for_the_next_cycle():
    twin = SimBackend(load_model("zu5"))
    twin.start()
    try:
        assert twin.servo_enable(True).ok
        physics, cycle = twin._physics, twin._physics.cycle
        time.sleep(0.1)
        q = physics.servo.setpoint.copy()     # where the drives hold the arm
        early_window = 0
        for trial in range(12):
            q = q + (STEP_RAD if trial % 2 == 0 else -STEP_RAD)
            last = physics.sample().stamp                   # a cycle's nominal end
            start = last + 2 * cycle                        # a cycle start still ahead
            while time.time() < start + AFTER_START_S:      # spin: sleep is too coarse
                pass
            sent = time.time()
            assert twin.servo_j(q).ok
            early_window += sent - start < 0.15e-3          # before the physics wakes
            # The cycle it arrived in ends at the first stamp at or after the send.
            arrival_end = last + np.ceil((sent - last) / cycle - 1e-9) * cycle
            time.sleep(6 * cycle)
            before = _sample_at(physics, arrival_end - cycle).q
            own = _sample_at(physics, arrival_end).q
            next_ = _sample_at(physics, arrival_end + cycle).q
            assert np.max(np.abs(own - before)) < 0.1 * STEP_RAD, (
                f"trial {trial}: sent {1e3 * (sent - start):.3f} ms into a cycle, the target "
                "was already reached at that cycle's end")
            moved = np.abs(next_ - before)
            assert np.all(moved > 0.5 * STEP_RAD), f"trial {trial}: not reached a cycle later"
        assert early_window >= 6, f"only {early_window} of 12 sends fell before the wake-up"
    finally:
        twin.shutdown()
