"""The twin's real-time loop: MuJoCo stepped in its own thread, paced to wall-clock time.

Every physics step (``timestep``, 1 ms by default) the servo drives compute torques; every
``cycle`` (8 ms, the JAKA controller period) the active motion source gives the next setpoint.
The loop wakes every ``wake_period`` (2 ms) and steps as many times as wall-clock time asks,
so it runs at 500 wake-ups/s while physics keeps a 1 kHz step.

Samples: after each batch the measured joints are copied; ``sample()`` returns the latest
copy with its wall-clock time. Hooks run inside the loop (``on_step`` after each step, for
contact checks) and must be quick.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Callable, Optional

import mujoco
import numpy as np

from .motions import Hold, Motion
from .servo import JointServo


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
                 cycle: float = 0.008, wake_period: float = 0.002):
        self.m = m
        self.d = mujoco.MjData(m)
        self.servo = servo
        self.cycle = cycle
        self.steps_per_cycle = max(1, round(cycle / m.opt.timestep))
        self.wake_period = wake_period
        self.lock = threading.RLock()
        self.d.qpos[:6] = q0
        mujoco.mj_forward(m, self.d)
        servo.reset(np.asarray(q0, float))
        self._motion: Motion = Hold()
        self._step_count = 0
        self._tau = np.zeros(6)
        self._sample: Optional[Sample] = None
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

    def _run(self) -> None:
        dt = self.m.opt.timestep
        start = time.monotonic()
        self.wall0 = time.time() - self.d.time
        done = 0
        while not self._quit.is_set():
            due = int((time.monotonic() - start) / dt) - done
            if due > 200:
                # The machine stalled for > 0.2 s: skip ahead instead of bursting through
                # hundreds of steps, and keep sample stamps on wall-clock time.
                self.overruns += 1
                self.wall0 += (due - 2) * dt
                done += due - 2
                due = 2
            with self.lock:
                for _ in range(due):
                    self._step(dt)
                self._record()
            done += due
            time.sleep(max(0.0, start + done * dt + self.wake_period - time.monotonic()))

    def _step(self, dt: float) -> None:
        m, d = self.m, self.d
        if self._step_count % self.steps_per_cycle == 0:
            q_sp = self._motion.next(self.servo.setpoint, self.servo.setpoint_velocity,
                                     d.qpos[:6], d.qvel[:6])
            self.servo.new_setpoint(np.asarray(q_sp, float))
            for hook in self.on_cycle:
                hook()
        self._step_count += 1
        mujoco.mj_step1(m, d)
        self._tau = self.servo.torque(d, dt)
        d.qfrc_applied[:6] = self._tau
        mujoco.mj_step2(m, d)
        self.steps_total += 1
        for hook in self.on_step:
            hook(d)

    def _record(self) -> None:
        d = self.d
        self._sample = Sample(stamp=self.wall0 + d.time, q=d.qpos[:6].copy(),
                              qd=d.qvel[:6].copy(), tau=self._tau.copy(),
                              moving=self._motion.moving)
