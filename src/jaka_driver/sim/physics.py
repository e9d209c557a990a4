"""The twin's real-time loop: MuJoCo stepped in its own thread, paced to wall-clock time
(or, with a simulated clock, whenever ``jaka_driver.backend.clock.SimClock`` lets a cycle start).

Every ``cycle`` (8 ms, the JAKA controller period) the active motion source gives the next
setpoint; the joint drives that follow it between setpoints are MuJoCo actuators
(:mod:`servo`), so a cycle is one ``mj_step(m, d, nstep=8)`` call at the 1 ms physics step,
with no Python between the steps. The loop wakes once per cycle, at the wall-clock cycle
boundary, and steps the cycle that has just elapsed (more after a stall): 125 wake-ups/s.
At the end of each cycle the checks run (contacts, overload: ``on_cycle``), then the motion
source chooses the setpoint of the next cycle from the commands that arrived by that cycle's
nominal end (:attr:`PhysicsLoop.cycle_end`; the loop wakes a little after it) — as a
controller does: a command is never acted on in physics time before it arrived, and it takes
effect in the cycle after the one it arrived in, by the samples' stamps. The sample of a
cycle exists the moment its wake-up is done.

Samples: at the end of each cycle the measured joints are copied; ``sample()`` returns the
latest copy with its wall-clock time, ``samples_since`` the recent ones, and
``wait_for_sample`` lets a publisher send each sample as soon as it exists. The checks in
``on_cycle`` run inside the loop, once per cycle, and must be quick.
"""
from __future__ import annotations

import threading
import time
from collections import deque
from typing import Callable, NamedTuple, Optional

import mujoco
import numpy as np

from ..common.constants import SERVO_CYCLE, STALL_CYCLES
from ..host import realtime
from .motions import Hold, Motion
from .servo import JointServo


# Cycles after which a late wake-up counts as a stall and time is skipped, not caught up.
HISTORY = 32                        # samples kept for readers that fell behind (0.26 s)
WAKE_MARGIN = 0.0002                # s
_NO_TORQUE = np.zeros(6)            # N·m: joints held by their brakes
_NO_TORQUE.flags.writeable = False


class Sample(NamedTuple):
    """Measured joints at ``stamp`` (s: wall-clock time, or sim time when the twin owns
    time): rad, rad/s, N·m; the force/torque sensor's reading of the cycle (None: no sensor,
    or off); ``status``, what the backend reports beside the physics as it stood when the
    sample was recorded (:attr:`PhysicsLoop.status_reading`). A named tuple: one is made every
    cycle, and a tuple is made in a third of a frozen dataclass's time."""

    stamp: float
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    moving: bool
    force: object = None
    status: object = None


class PhysicsLoop:
    """Owns ``MjData``; all access to it happens in the loop thread (or under ``lock``)."""

    def __init__(self, m: mujoco.MjModel, servo: JointServo, q0: np.ndarray,
                 cycle: float = SERVO_CYCLE, clock=None):
        self.m = m
        self.d = mujoco.MjData(m)
        self.servo = servo
        self.steps_per_cycle = servo.steps
        self.cycle = self.steps_per_cycle * m.opt.timestep
        self.lock = threading.RLock()
        self._sampled = threading.Condition()
        self.d.qpos[:6] = q0
        # The measured joints (rad, rad/s): views made once (MjData's arrays stay where they are)
        self._q, self._qd = self.d.qpos[:6], self.d.qvel[:6]
        mujoco.mj_forward(m, self.d)
        servo.reset(np.asarray(q0, float))
        self._motion: Motion = Hold()
        self._tau = np.zeros(6)
        self._braked = False          # joints locked where they stand, drives off
        self._sample: Optional[Sample] = None
        self._history: deque[Sample] = deque(maxlen=HISTORY)
        self._quit = threading.Event()
        self._thread: Optional[threading.Thread] = None
        # Checks at each cycle's end, before the next setpoint is chosen (contacts, overload).
        self.on_cycle: list[Callable[[mujoco.MjData], None]] = []
        #: the force/torque sensor's latest reading, recorded with each sample (a twin with a
        #: sensor sets it: sim/force.py)
        self.force_reading: Callable[[], object] = lambda: None
        #: the backend's flags, modes and IO, recorded with each sample (sim/backend.py): a
        #: sample published later still says what stood at its stamp. Called with ``lock``
        #: held, so it takes no lock a request may hold while it waits for this one.
        self.status_reading: Callable[[], object] = lambda: None
        #: None: paced to the wall clock, samples stamped in wall time; a
        #: :class:`jaka_driver.backend.clock.SimClock`: the twin owns time, samples stamped in it
        self.clock = clock
        self.wall0 = 0.0 if self.simulated else time.time()
        self._start = time.monotonic()
        self._done = 0                              # cycles stepped since start()
        #: Nominal end of the cycle being stepped, on :meth:`arrival_time`'s clock: commands
        #: that arrived by then count for the setpoint chosen at its end (motions.ServoTarget).
        self.cycle_end = float("-inf")
        self.steps_total = 0
        self.overruns = 0
        self._record()

    # ---- motion sources ---------------------------------------------------------------
    @property
    def motion(self) -> Motion:
        return self._motion

    def switch(self, motion: Motion) -> Motion:
        """Make ``motion`` the active source from the next cycle; returns the previous one
        (the caller decides what its waiting client is told)."""
        with self.lock:
            previous, self._motion = self._motion, motion
            return previous

    def hold_here(self) -> Motion:
        """Halt within one cycle at the measured position (protective stop, e-stop)."""
        return self.hold_at(self.d.qpos[:6].copy())

    def hold_at(self, q: np.ndarray) -> Motion:
        """Halt within one cycle and hold ``q`` (rad), a pose the arm has just passed."""
        with self.lock:
            self.servo.reset(np.asarray(q, float).copy())
            return self.switch(Hold())

    def reset(self, q: np.ndarray) -> Motion:
        """The arm at rest at ``q`` (rad) as at a fresh start — MuJoCo's state reset, drives
        holding ``q``, brakes open, nothing moving — with time running on (``d.time`` is
        kept: stamps never go back). Returns the motion source it replaced."""
        with self.lock:
            t = self.d.time
            mujoco.mj_resetData(self.m, self.d)
            self.d.time = t
            self.d.qpos[:6] = q
            mujoco.mj_forward(self.m, self.d)
            self.servo.reset(np.asarray(q, float).copy())
            self._braked = False
            self._tau = np.zeros(6)
            previous = self.switch(Hold())
            self._record()
            return previous

    def step_cycle(self) -> None:
        """One cycle now, outside the real-time thread (tests and benchmarks that step the
        twin themselves, the thread not started): every command that has arrived counts
        for the setpoint chosen at its end."""
        with self.lock:
            self.cycle_end = self.arrival_time()
            self._cycle()

    def arrival_time(self) -> float:
        """Now, on the clock :attr:`cycle_end` counts in: monotonic s on the wall clock (the
        pacing's own), sim s in sim time."""
        return self.clock.now() if self.simulated else time.monotonic()

    def checked_pose(self) -> np.ndarray:
        """The joints (rad) at the end of the last cycle whose checks passed: during the
        checks of a cycle, the previous cycle's sample."""
        return self._sample.q

    # ---- brakes -------------------------------------------------------------------------
    @property
    def braked(self) -> bool:
        return self._braked

    def engage_brakes(self) -> Motion:
        """Close the joint brakes where the arm is: from the next cycle the joints are locked
        (positions held exactly, velocities 0) and the drives give no torque."""
        with self.lock:
            self._braked = True
            self.d.qvel[:6] = 0.0
            self._record()      # locked from now: a client told so sees it in the sample
            return self.hold_here()

    def release_brakes(self) -> None:
        """Open the brakes: the drives hold the arm where the brakes had it."""
        with self.lock:
            if self._braked:
                self._braked = False
                self.servo.reset(self.d.qpos[:6].copy())

    # ---- thread -------------------------------------------------------------------------
    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="twin-physics", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._quit.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)

    def sample(self) -> Sample:
        return self._sample

    def samples_since(self, after: float) -> list[Sample]:
        """The recent samples (one per cycle, the last ``HISTORY`` cycles) stamped later than
        ``after`` (s), oldest first: a reader that fell behind, or a loop that caught up
        several cycles at once, still gets every cycle."""
        newer = []
        # A copy (atomic, in C): the physics thread appends meanwhile. Newest first: usually
        # one sample is new.
        for s in reversed(list(self._history)):
            if s.stamp <= after:
                break
            newer.append(s)
        newer.reverse()
        return newer

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """Block until the latest sample is stamped later than ``after`` (s), at most
        ``timeout`` s; True if it is."""
        with self._sampled:
            return self._sampled.wait_for(lambda: self._sample.stamp > after, timeout)

    @property
    def simulated(self) -> bool:
        return self.clock is not None and self.clock.simulated

    @realtime.runs_periodically
    def _run(self) -> None:
        if self.simulated:
            self._run_in_sim_time()
        else:
            self._run_on_the_wall_clock()

    def _run_in_sim_time(self) -> None:
        """One cycle whenever the clock lets the next one start (its pacing and holds,
        jaka_driver.backend.clock); sample stamps are sim time (``d.time``)."""
        clock = self.clock
        while clock.wait_for_cycle(self._quit):
            with self.lock:
                self.cycle_end = clock.now() + self.cycle
                self._cycle()
            clock.tick()
            with self._sampled:
                self._sampled.notify_all()

    def _run_on_the_wall_clock(self) -> None:
        self._start = time.monotonic()
        self._done = 0
        self.wall0 = time.time() - self.d.time
        while not self._quit.is_set():
            due = self._wait_for_cycles()
            if due == 0:
                continue
            with self.lock:
                for i in range(due):
                    self.cycle_end = self._start + (self._done + i + 1) * self.cycle
                    self._cycle()
            with self._sampled:
                self._sampled.notify_all()
            self._done += due

    def _wait_for_cycles(self) -> int:
        """Pacing to the wall clock: the number of whole cycles that have elapsed and are not
        stepped yet, after sleeping until just past the next cycle boundary if none has.
        After a stall of more than ``STALL_CYCLES`` it skips ahead instead of bursting
        through dozens of cycles, keeping sample stamps on wall-clock time."""
        cycle = self.cycle
        due = int((time.monotonic() - self._start) / cycle) - self._done
        if due > STALL_CYCLES:
            self.overruns += 1
            self.wall0 += (due - 1) * cycle
            self._done += due - 1
            return 1
        if due > 0:
            return due
        # The 0.2 ms margin keeps a slightly early wake-up from finding no whole cycle due.
        time.sleep(max(0.0, self._start + (self._done + 1) * cycle + WAKE_MARGIN
                       - time.monotonic()))
        return 0

    def _cycle(self) -> None:
        """Step one cycle, check it, choose the next setpoint and record the sample."""
        d = self.d
        if not self._braked:
            self.servo.step(d)
            self._tau = self.servo.tau
        else:
            # Joints locked by their brakes (the arm is all there is that moves): nothing to
            # integrate, the drives give no torque.
            d.time += self.cycle
            self._tau = _NO_TORQUE
        self.steps_total += self.steps_per_cycle
        for check in self.on_cycle:
            check(d)
        # The cycle ends: the setpoint for the next one, from what has arrived by now.
        servo = self.servo
        servo.new_setpoint(self._motion.next(servo.setpoint, servo.setpoint_velocity,
                                             self._q, self._qd))
        self._record()

    def _record(self) -> None:
        self._sample = Sample(self.wall0 + self.d.time, self._q.copy(), self._qd.copy(),
                              self._tau.copy(), self._motion.moving, self.force_reading(),
                              self.status_reading())
        self._history.append(self._sample)
