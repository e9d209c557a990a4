"""A stepped twin replays bit for bit, whatever the machine's load and the real-time factor.

One scripted scenario (support/stepped_scenario.py: moves, a jog and twists left to their
watchdogs, a servo stream with a gap, a trajectory with a future start, a program with a
``wait`` and a ``wait_input``, force zeroing and constant force on the table) runs three times
on a paused twin its script steps: at real_time_factor 1 on a quiet machine, at 1 with both
cores kept busy by two busy-looping processes, and at 0 (as fast as it steps) under the same
load. Every sample of the three runs — what ``joint_position``, ``robot_states`` and ``wrench``
publish: joints, velocities, torques, TCP, every flag, program state, IO, wrench, and the stamp
— is the same to the bit, and so are the trajectory monitor's checks (their times and errors).
A timer acting when its thread happened to wake would shift a stop by cycles under load."""
import numpy as np
import pytest

from bench.cpu_load import BusyLoad
from support.stepped_scenario import differences, run

from jaka_driver.common.constants import SERVO_CYCLE as CYCLE


@pytest.fixture(scope="module")
def quiet():
    return run(real_time_factor=1.0)


def test_the_scenario_does_what_it_claims(quiet):
    """The streams compared are not trivially equal: the arm moves, the jog stops 3 s after
    its call, the program runs, the probe presses 10 N."""
    t = np.array([s.stamp for s in quiet.states])
    assert len(t) == quiet.cycles + 1, (len(t), quiet.cycles)             # every cycle once
    assert np.allclose(np.diff(t), CYCLE)
    moving = np.array([np.max(np.abs(s.joint_velocity)) > 1e-3 for s in quiet.states])
    assert 0.4 < moving.mean() < 0.9, moving.mean()
    programs = {s.program_state for s in quiet.states}
    assert programs == {0, 1}, programs
    pressed = [-s.force.actual[2] for s in quiet.states[-60:-40] if s.force is not None]
    assert pressed and abs(np.mean(pressed) - 10.0) < 0.5, pressed
    assert len(quiet.monitored) > 50                                   # 50 Hz for 1.4 s


@pytest.mark.parametrize("factor", [1.0, 0.0])
def test_with_both_cores_busy_every_sample_is_the_same_to_the_bit(quiet, factor):
    loaded = run(real_time_factor=factor, load=BusyLoad(2))     # killed when the run ends
    found, worst = differences(quiet, loaded)
    print(f"real_time_factor {factor:g}, both cores busy: {quiet.cycles} cycles, "
          f"{len(found)} differences, worst {worst:g}")
    assert found == [], found[:10]
    assert worst == 0.0
