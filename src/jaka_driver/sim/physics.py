"""The twin's real-time loop: MuJoCo stepped in its own thread, paced to wall-clock time.

Every physics step (``timestep``, 1 ms by default) the servo drives compute torques; every
``cycle`` (8 ms, the JAKA controller period) the active motion source gives the next setpoint.
The loop wakes once per cycle, at the wall-clock cycle boundary, and steps the cycle that has
just elapsed (8 steps; more after a stall): 125 wake-ups/s while physics keeps a 1 kHz step.
At the end of each cycle the motion source chooses the setpoint of the next one, from the
commands that have arrived by then — as a controller does: a command is never acted on in
physics time before it arrived, and it takes effect in the cycle after the one it arrived in.
The sample of a cycle exists the moment its wake-up is done.

Samples: at the end of each cycle the measured joints are copied; ``sample()`` returns the
latest copy with its wall-clock time, ``samples_since`` the recent ones, and
``wait_for_sample`` lets a publisher send each sample as soon as it exists. Hooks run inside the loop (``on_step`` after each step, for contact checks;
``on_cycle`` at each cycle boundary) and must be quick.
"""
from __future__ import annotations

import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Callable, Optional

import mujoco
import numpy as np

from ..constants import SERVO_CYCLE
from .motions import Hold, Motion
from .servo import JointServo


# Cycles after which a late wake-up counts as a stall and time is skipped, not caught up.
STALL_CYCLES = 25                   # 0.2 s at 8 ms
HISTORY = 32                        # samples kept for readers that fell behind (0.26 s)
WAKE_MARGIN = 0.0002                # s


@dataclass(frozen=True)
class Sample:
    """Measured joints at wall-clock ``stamp`` (s): rad, rad/s, N·m."""

    stamp: float
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    moving: bool


class PhysicsLoop:
    """Owns ``MjData``; all access to it happens in the loop thread (or under ``lock``)."""

    def __init__(self, m: mujoco.MjModel, servo: JointServo, q0: np.ndarray,
                 cycle: float = SERVO_CYCLE):
        self.m = m
        self.d = mujoco.MjData(m)
        self.servo = servo
        self.steps_per_cycle = max(1, round(cycle / m.opt.timestep))
        self.cycle = self.steps_per_cycle * m.opt.timestep
        self.lock = threading.RLock()
        self._sampled = threading.Condition()
        self.d.qpos[:6] = q0
        mujoco.mj_forward(m, self.d)
        servo.reset(np.asarray(q0, float))
        self._motion: Motion = Hold()
        self._step_count = 0
        self._tau = np.zeros(6)
        self._brakes: Optional[np.ndarray] = None     # joint angles the brakes lock, rad
        self._sample: Optional[Sample] = None
        self._history: deque[Sample] = deque(maxlen=HISTORY)
        self._quit = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self.on_step: list[Callable[[mujoco.MjData], None]] = []
        self.on_cycle: list[Callable[[], None]] = []
        self.wall0 = time.time()
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
        with self.lock:
            self.servo.reset(self.d.qpos[:6].copy())
            return self.switch(Hold())

    # ---- brakes -------------------------------------------------------------------------
    @property
    def braked(self) -> bool:
        return self._brakes is not None

    def engage_brakes(self) -> Motion:
        """Close the joint brakes where the arm is: from the next step the joints are locked
        (positions held exactly, velocities 0) and the drives give no torque."""
        with self.lock:
            self._brakes = self.d.qpos[:6].copy()
            self.d.qvel[:6] = 0.0
            self._record()      # locked from now: a client told so sees it in the sample
            return self.hold_here()

    def release_brakes(self) -> None:
        """Open the brakes: the drives hold the arm where the brakes had it."""
        with self.lock:
            if self._brakes is not None:
                self._brakes = None
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
        return [s for s in list(self._history) if s.stamp > after]

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """Block until the latest sample is stamped later than ``after`` (s), at most
        ``timeout`` s; True if it is."""
        with self._sampled:
            return self._sampled.wait_for(lambda: self._sample.stamp > after, timeout)

    def _run(self) -> None:
        dt, cycle = self.m.opt.timestep, self.cycle
        start = time.monotonic()
        self.wall0 = time.time() - self.d.time
        done = 0                                    # cycles stepped
        while not self._quit.is_set():
            due = int((time.monotonic() - start) / cycle) - done
            if due > STALL_CYCLES:
                # The machine stalled: skip ahead instead of bursting through dozens of
                # cycles, and keep sample stamps on wall-clock time.
                self.overruns += 1
                self.wall0 += (due - 1) * cycle
                done += due - 1
                due = 1
            if due > 0:
                with self.lock:
                    for _ in range(due * self.steps_per_cycle):
                        self._step(dt)
                with self._sampled:
                    self._sampled.notify_all()
                done += due
            # Wake just after the next cycle boundary (the 0.2 ms margin keeps a slightly
            # early wake-up from finding no whole cycle due).
            time.sleep(max(0.0, start + (done + 1) * cycle + WAKE_MARGIN - time.monotonic()))

    def _step(self, dt: float) -> None:
        m, d = self.m, self.d
        self._step_count += 1
        mujoco.mj_step1(m, d)
        brakes = self._brakes
        self._tau = self.servo.torque(d, dt) if brakes is None else np.zeros(6)
        d.qfrc_applied[:6] = self._tau
        mujoco.mj_step2(m, d)
        if brakes is not None:
            d.qpos[:6] = brakes
            d.qvel[:6] = 0.0
        self.steps_total += 1
        for hook in self.on_step:
            hook(d)
        if self._step_count % self.steps_per_cycle == 0:
            # The cycle ends: the setpoint for the next one, from what has arrived by now.
            q_sp = self._motion.next(self.servo.setpoint, self.servo.setpoint_velocity,
                                     d.qpos[:6], d.qvel[:6])
            self.servo.new_setpoint(np.asarray(q_sp, float))
            for hook in self.on_cycle:
                hook()
            self._record()

    def _record(self) -> None:
        d = self.d
        self._sample = Sample(stamp=self.wall0 + d.time, q=d.qpos[:6].copy(),
                              qd=d.qvel[:6].copy(), tau=self._tau.copy(),
                              moving=self._motion.moving)
        self._history.append(self._sample)
