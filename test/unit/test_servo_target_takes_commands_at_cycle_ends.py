"""ServoTarget takes each command at the first cycle end after the command arrived (by the
cycle clock it is given), in order; a hold acts at once and drops what was not taken."""
import numpy as np

from jaka_driver.sim.motions import ServoTarget

Q0, Q1, Q2 = np.zeros(6), np.full(6, 0.1), np.full(6, 0.2)


class Cycles:
    """A cycle clock that the test sets by hand (s)."""

    def __init__(self):
        self.now = 0.0
        self.cycle_end = 0.0

    def arrival_time(self) -> float:
        return self.now


def _choose(target: ServoTarget, cycles: Cycles, cycle_end: float) -> np.ndarray:
    cycles.cycle_end = cycle_end
    return target.next(Q0, Q0, Q0, Q0)


def test_a_command_that_arrives_after_a_cycle_end_waits_for_the_next_one():
    cycles = Cycles()
    target = ServoTarget(Q0, cycles)
    cycles.now = 1.0005                     # cycle [1.000, 1.008] has begun
    target.set(Q1)
    assert np.array_equal(_choose(target, cycles, 1.000), Q0)    # the late choice at 1.000
    assert np.array_equal(target.goal, Q1) and np.array_equal(target.latest, Q1)
    assert np.array_equal(_choose(target, cycles, 1.008), Q1)


def test_commands_are_taken_in_order_and_a_ramp_starts_where_the_set_left_off():
    cycles = Cycles()
    target = ServoTarget(Q0, cycles)
    cycles.now = 0.999
    target.set(Q1)
    target.ramp(Q2 + 0.1, 2)                # from Q1 to 0.3 in two cycles
    first = _choose(target, cycles, 1.000)
    assert np.allclose(first, 0.2)
    assert np.allclose(_choose(target, cycles, 1.008), 0.3)


def test_a_hold_acts_at_the_next_choice_and_drops_what_was_not_taken():
    cycles = Cycles()
    target = ServoTarget(Q0, cycles)
    cycles.now = 1.0005
    target.set(Q2)
    target.hold(Q1)                         # a stop, arriving after the cycle end too
    assert np.array_equal(_choose(target, cycles, 1.000), Q1)
    assert np.array_equal(_choose(target, cycles, 1.008), Q1)
    assert np.array_equal(target.goal, Q1)
