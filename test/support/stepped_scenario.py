"""A scripted scenario on a paused twin that its script steps, exercising every timer of the
driver and the twin, and every sample it produced — for the determinism test and its bench
row (docs/twin.md, "Simulated time").

The script acts only between steps, as a ROS client calling ``~sim/step`` does: moves, a jog
left to its 3 s watchdog, twists left to their 0.1 s watchdog, a servo stream with a 0.2 s gap,
a trajectory (FollowJointTrajectory's path: its start at a future stamp, its 50 Hz checks), a
program with a ``wait`` and a ``wait_input`` (the input set while it polls), then at home over
the table force zeroing and 10 N of constant force. A blocking call (a move, zeroing) runs in
a thread of its own, which holds time until it waits on the clock, so it starts in the cycle
the script reached, not when its thread got a core. Every sample is kept: :func:`differences`
compares two runs field by field, stamp by stamp.
"""
from __future__ import annotations

import dataclasses
import tempfile
import threading
from contextlib import nullcontext
from pathlib import Path

import numpy as np

from jaka_driver.backend.robot_state import RobotState
from jaka_driver.common.constants import SERVO_CYCLE as CYCLE
from jaka_driver.common.models import load_model, repo_root
from jaka_driver.driver import RobotDriver
from jaka_driver.motion.spline import Waypoint, sample_waypoints
from jaka_driver.motion.trajectory import JointTrajectory
from jaka_driver.programs import FolderPrograms
from jaka_driver.sim import SimBackend

from support.twin_samples import Collector

MODEL = load_model("zu5")
TABLE = str(repo_root() / "config" / "scenes" / "table.yaml")
RAISED = [0.0, 1.9, -1.4, 1.0, 1.5708, 0.0]        # flange 0.59 m up: clear of the table
A = [0.5, 1.2, -1.0, 1.9, 1.2, 0.8]
B = [0.3, 1.4, -1.3, 1.7, 1.4, 0.3]
PROGRAM = f"""\
# determinism: a move, an output, a wait, an input polled every cycle, a move back
joint_move {B} speed 1.5 accel 4
set_output digital cabinet 3 = 1
wait 0.25
wait_input digital cabinet 5 == 1 timeout 3
set_output digital cabinet 3 = 0
joint_move {RAISED} speed 1.5 accel 4
"""
WAIT_INPUT_LINE = 5
MOST_CYCLES = 2000             # a blocking call or the program ends within this many cycles


class Background:
    """``fn(*args)`` in a thread of its own that holds ``clock`` from before it starts (so it
    acts at the cycle the script has reached); ``done`` is set, still holding, once it
    returned (so a step after which it ended is answered after it)."""

    def __init__(self, clock, fn, *args, **kwargs):
        self.done, self.result = threading.Event(), None
        entered = threading.Event()

        def run():
            with clock.hold(react=False):
                entered.set()
                self.result = fn(*args, **kwargs)
                self.done.set()

        self.thread = threading.Thread(target=run, name="scenario-call", daemon=True)
        self.thread.start()
        assert entered.wait(5.0), "the call's thread did not start"


class Script:
    """The scenario's client: requests through the driver's door, time through
    ``step_twin``."""

    def __init__(self, driver: RobotDriver):
        self.driver, self.clock = driver, driver.clock
        self.monitored: list[tuple[float, float]] = []     # trajectory checks: (t, worst error)

    def ok(self, result):
        assert result.ok, result.message
        return result

    def step(self, cycles: int) -> None:
        self.ok(self.driver.twin.step(int(cycles)))

    def seconds(self, s: float) -> None:
        self.step(round(s / CYCLE))

    def finish(self, call: Background, chunk: int = 5):
        """Step ``chunk`` cycles at a time until ``call`` has returned; its result."""
        for _ in range(MOST_CYCLES // chunk):
            if call.done.is_set():
                call.thread.join(5.0)
                return self.ok(call.result)
            self.step(chunk)
        raise AssertionError(f"the call did not end within {MOST_CYCLES} cycles")

    def blocking(self, fn, *args, **kwargs):
        return self.finish(Background(self.clock, fn, *args, **kwargs))

    def until(self, condition, chunk: int = 5) -> None:
        for _ in range(MOST_CYCLES // chunk):
            if condition():
                return
            self.step(chunk)
        raise AssertionError(f"not reached within {MOST_CYCLES} cycles")

    # ---- the scenario's parts --------------------------------------------------------------
    def moves(self) -> None:
        d = self.driver
        self.blocking(d.joint_move, A, 1.5, 4.0)
        self.ok(d.set_io("digital", 0, 2, 1))
        pose = d.get_fk(d.state().joint_position).value.copy()
        pose[2] += 50.0                                     # mm up
        self.blocking(d.linear_move, pose, 200.0, 1000.0, coord_mode=1)

    def jog_left_to_its_watchdog(self) -> None:
        self.ok(self.driver.jog(0, 0, 0.3))
        self.seconds(3.5)                                   # it stops 3 s after the call
        assert self.driver.state().joint_velocity[0] == 0.0 or not self.driver.moving

    def twists_left_to_their_watchdog(self) -> None:
        for _ in range(13):                                 # every 2 cycles for 0.2 s
            self.ok(self.driver.velocity_jog([0.0, 0.01, 0.02], [0.0, 0.0, 0.1], False))
            self.step(2)
        self.seconds(0.5)                                   # stops 0.1 s after the last
        assert not self.driver.moving

    def servo_stream_with_a_gap(self) -> None:
        d = self.driver
        self.ok(d.servo_move_enable(True))
        q0 = d.state().joint_position.copy()
        swing = np.array([0.04, -0.02, 0.03, 0.0, 0.0, 0.06])      # rad, a 0.8 s sine
        for k in list(range(1, 41)) + [None] + list(range(41, 61)):
            if k is None:
                self.step(25)                               # 0.2 s without a target
                continue
            self.ok(d.servo_j(q0 + swing * np.sin(np.pi * k / 50)))
            self.step(1)
        self.ok(d.servo_move_enable(False))
        self.step(5)

    def trajectory(self) -> None:
        d = self.driver
        q0 = d.state().joint_position.copy()
        waypoints = [Waypoint(0.6, np.asarray(B, float), None, None),
                     Waypoint(1.4, np.asarray(RAISED, float), np.zeros(6), None)]
        times, q, qd = sample_waypoints(q0, waypoints, CYCLE)
        trajectory = JointTrajectory(times=times, q=q, qd=qd)

        def monitor(t, st):                                 # as the action's path check
            desired, _ = trajectory.sample(t)
            worst = float(np.max(np.abs(desired - st.joint_position)))
            self.monitored.append((t, worst))
            return None if worst < 0.2 else f"path error {worst:.3f} rad at t = {t:.2f} s"

        start_at = d.state().stamp + 0.1                    # a header.stamp 0.1 s ahead
        self.blocking(d.follow_trajectory, trajectory, monitor, start_at=start_at)

    def program(self, folder: Path) -> None:
        d = self.driver
        (folder / "determinism.jdp").write_text(PROGRAM)
        self.ok(d.programs.load("determinism"))
        self.ok(d.programs.play())
        self.until(lambda: d.programs.status().line == WAIT_INPUT_LINE)
        self.step(30)                                       # it polls the input every cycle
        self.ok(d.twin.set_input("digital", 0, 5, 1))
        self.until(lambda: d.programs.status().state == 0)
        status = d.programs.status()
        assert status.error == "", status.error

    def force(self) -> None:
        d, f = self.driver, self.driver.force
        self.ok(d.twin.reset())                             # home, over the table
        self.ok(f.sensor_enable(True))
        self.seconds(0.2)
        self.blocking(f.zero_sensor)
        self.ok(f.set_admittance(2, 1, 40.0, 0.0, 10.0))    # press 10 N along the tool's z
        self.ok(f.set_compliance_type(True, 1))
        self.ok(f.enable_admittance(True))
        self.seconds(1.5)
        self.ok(f.disable())
        self.seconds(0.3)


@dataclasses.dataclass
class Run:
    """One run: every sample (oldest first), the trajectory monitor's checks, the cycles."""

    states: list[RobotState]
    monitored: list[tuple[float, float]]
    cycles: int


def run(real_time_factor: float, load=None) -> Run:
    """The scenario once on a fresh twin at ``real_time_factor``, inside ``load`` (a context
    manager keeping the cores busy, or None)."""
    with tempfile.TemporaryDirectory() as folder, (load or nullcontext()):
        driver = RobotDriver(SimBackend(MODEL, scene=TABLE, force_sensor=True, sim_time=True,
                                        real_time_factor=real_time_factor,
                                        programs=FolderPrograms(folder)))
        assert driver.twin.pause(True).ok                   # no cycle before the script's
        samples = Collector(driver)
        try:
            driver.start()
            script = Script(driver)
            script.ok(driver.twin.reset(RAISED))
            script.step(5)
            script.moves()
            script.jog_left_to_its_watchdog()
            script.twists_left_to_their_watchdog()
            script.servo_stream_with_a_gap()
            script.trajectory()
            script.program(Path(folder))
            script.force()
            end = driver.clock.cycles
            # (stamps add up 8 ms a cycle in floating point: 1e-6 s below the cycle's end)
            states = samples.since(-1.0, until=end * CYCLE - 1e-6)
        finally:
            samples.close()
            driver.shutdown()
    return Run([s for s in states if s.stamp <= end * CYCLE + 1e-6], script.monitored, end)


def _fields(state: RobotState) -> dict:
    """Every field of a sample, each as what its bits say (arrays as bytes, floats as hex)."""
    def bits(value):
        if isinstance(value, np.ndarray):
            return (value.dtype.str, value.shape, value.tobytes())
        if isinstance(value, float):
            return value.hex()
        if isinstance(value, tuple):
            return tuple(bits(v) for v in value)
        if hasattr(value, "items"):
            return tuple(sorted((k, bits(v)) for k, v in value.items()))
        return value
    return {f.name: bits(getattr(state, f.name)) for f in dataclasses.fields(state)}


def differences(a: Run, b: Run) -> tuple[list[str], float]:
    """(every field of every sample that differs, as "cycle n: field"; the worst difference
    of the joints, velocities, torques and wrenches, rad / rad/s / N·m / N)."""
    found, worst = [], 0.0
    if a.cycles != b.cycles or len(a.states) != len(b.states):
        return [f"runs of {a.cycles} / {b.cycles} cycles, {len(a.states)} / "
                f"{len(b.states)} samples"], float("inf")
    for x, y in zip(a.states, b.states):
        fx, fy = _fields(x), _fields(y)
        found += [f"cycle {round(x.stamp / CYCLE)}: {name}" for name in fx if fx[name] != fy[name]]
        arrays = [(x.joint_position, y.joint_position), (x.joint_velocity, y.joint_velocity),
                  (x.joint_effort, y.joint_effort)]
        if x.force is not None and y.force is not None:
            arrays += [(x.force.actual, y.force.actual), (x.force.real, y.force.real)]
        worst = max([worst] + [float(np.max(np.abs(p - q))) for p, q in arrays])
    if a.monitored != b.monitored:
        found.append("the trajectory monitor's checks")
    return found, worst
