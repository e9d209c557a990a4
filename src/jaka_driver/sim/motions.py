"""What the twin's controller does each 8 ms cycle: one motion source produces the next servo
setpoint. Exactly one source is active; the physics thread swaps them.

Sources: :class:`Hold` (stand still), :class:`TrajectoryRun` (joint_move / linear_move),
:class:`Jog`, :class:`ServoTarget` (servo mode), :class:`Stopping` (decelerate to rest).
A source that a blocking call waits on carries a :class:`Completion`.
"""
from __future__ import annotations

import threading
from collections import deque
from dataclasses import dataclass, field
from typing import Callable, Optional, Protocol

import numpy as np

from ..backend.completion import Completion
from ..common.results import Code, Result
from ..motion.jog import JogVelocity
from ..motion.trajectory import JointTrajectory
from ..motion.velocity_jog import VelocityJog

#: rad/s; with the position inside its tolerance, slower than this counts as arrived
SETTLED_SPEED = 0.05


class Motion:
    """A source of setpoints. ``next(q_sp, qd_sp, q_meas, qd_meas)`` returns the setpoint (rad)
    for the end of the coming cycle; ``active`` is False once the source only holds."""

    completion: Optional[Completion] = None
    active = True
    moving = True
    #: why a command that needs the arm still is refused while this source runs
    busy_reason = "the arm is still moving (stopping)"
    #: share of its own speed a move runs at (velocity compliance slows it: sim/force.py)
    pace = 1.0

    def next(self, q_sp, qd_sp, q_meas, qd_meas) -> np.ndarray:
        raise NotImplementedError

    def abort(self, result: Result) -> None:
        """Replaced before finishing: tell whoever waits."""
        if self.completion is not None:
            self.completion.finish(result)


class Hold(Motion):
    """Keep the last setpoint."""

    active = False
    moving = False

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        return q_sp


@dataclass(eq=False)
class TrajectoryRun(Motion):
    """Play a planned joint trajectory, then settle: success once every joint is within
    ``tolerance`` rad of the goal and almost at rest.

    It can be paused on its path, as a controller pauses a program: :meth:`pause` slows the
    trajectory's own time to a stop (its path unchanged: the setpoint is always a point of
    the planned path), :meth:`resume` brings it back to full speed and the move ends where it
    was planned to. The slowing takes ``|qd| / accel`` for the fastest joint (``accel`` rad/s²,
    the arm's limits), at least two cycles."""

    trajectory: JointTrajectory
    cycle: float                 # s
    tolerance: float             # rad
    label: str
    # every caller gives it; the default is only because Motion's class attribute is one
    completion: Optional[Completion] = None
    accel: Optional[np.ndarray] = None                 # rad/s², for pause and resume
    t: float = field(default=0.0, init=False)          # s into the trajectory
    goal: np.ndarray = field(init=False)
    rate: float = field(default=1.0, init=False)       # trajectory s per s (1 = as planned)
    _rate_to: float = field(default=1.0, init=False)
    _rate_step: float = field(default=1.0, init=False)  # per cycle
    _lock: threading.Lock = field(default_factory=threading.Lock, init=False)

    def __post_init__(self):
        self.goal = self.trajectory.q[-1]

    def pause(self) -> None:
        """Slow to rest on the path (from the physics thread's next cycle on)."""
        _, qd = self.trajectory.sample(self.t)
        self._ramp_to(0.0, np.abs(qd))

    def resume(self) -> None:
        """Back to the planned speed along the rest of the path."""
        self._ramp_to(1.0, np.max(np.abs(self.trajectory.qd), axis=0))

    @property
    def paused(self) -> bool:
        return self._rate_to == 0.0

    def _ramp_to(self, rate: float, speed: np.ndarray) -> None:
        accel = np.full_like(speed, np.inf) if self.accel is None else self.accel
        ramp = max(2.0 * self.cycle, float(np.max(speed / accel)))
        with self._lock:
            self._rate_to, self._rate_step = rate, self.cycle / ramp

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        # Called at the end of a cycle: the arm now stands where the setpoint of time
        # ``self.t`` put it; done only once that setpoint was the goal (not a cycle early,
        # on a measurement that is merely close to the goal while still decelerating).
        elapsed = self.t
        if elapsed >= self.trajectory.duration:
            self.moving = False
            error = np.max(np.abs(q_meas - self.goal))
            if error <= self.tolerance and np.max(np.abs(qd_meas)) < SETTLED_SPEED:
                self.active = False
                self.completion.finish(Result.success(
                    f"{self.label} done in {elapsed:.3f} s (planned "
                    f"{self.trajectory.duration:.3f} s), final error {error:.1e} rad"))
        with self._lock:
            to, step = self._rate_to, self._rate_step
        # the mean of the cycle's start and end rates: the path time the cycle covers, at the
        # pace velocity compliance sets (1 without it)
        start = self.rate
        self.rate = min(to, start + step) if to > start else max(to, start - step)
        self.t += 0.5 * (start + self.rate) * self.cycle * self.pace
        if elapsed < self.trajectory.duration:
            self.moving = self.rate > 0.0
        q, _ = self.trajectory.sample(self.t)
        return np.asarray(q, float)


class Stopping(Motion):
    """Decelerate every joint to rest at its stop deceleration (rad/s²), along the current
    direction of travel."""

    def __init__(self, decel: np.ndarray, cycle: float, on_rest: Optional[Callable] = None):
        self.decel = decel
        self.cycle = cycle
        self.velocity: Optional[np.ndarray] = None
        self._on_rest = on_rest

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        if self.velocity is None:
            self.velocity = qd_sp.copy()
        dv = self.decel * self.cycle
        self.velocity = np.sign(self.velocity) * np.maximum(np.abs(self.velocity) - dv, 0.0)
        if not self.velocity.any():
            self.active = self.moving = False
            if self._on_rest is not None:
                self._on_rest()
                self._on_rest = None
        return q_sp + self.velocity * self.cycle


class CycleClock(Protocol):
    """The twin's cycles as a servo target sees them (the physics loop is one): a command's
    arrival time and the nominal end of the cycle whose end chooses the next setpoint, on one
    clock (monotonic s on the wall clock, sim s in sim time)."""

    cycle_end: float

    def arrival_time(self) -> float: ...


class ServoTarget(Motion):
    """Servo mode: the latest servo_j / servo_p target, reached within one cycle — or, with
    ``stepNum`` (:meth:`ramp`), over ``n`` cycles interpolated linearly, as the controller
    does — each cycle through the servo filter, when one is chosen.

    A target takes effect in the cycle after the one it arrived in, by the cycles' nominal
    times (the sample stamps): the setpoint chosen at the end of cycle k takes the targets
    that arrived by cycle k's nominal end. The physics thread steps cycle k a little after
    that end (its wake-up margin and delay); a target that arrives in between belongs to
    cycle k + 1 and waits for the next choice, instead of joining cycle k + 1 early.
    """

    moving = False
    PENDING = 64        # commands kept for the coming choices (a stream brings one a cycle)

    def __init__(self, q: np.ndarray, cycles: CycleClock, servo_filter=None):
        """``servo_filter``: what the targets pass through each cycle before the drives follow
        them (jaka_driver.motion.servo_filters; None: nothing)."""
        self.target = q.copy()
        self._cycles = cycles
        self._ramp: Optional[tuple] = None   # (start, end, cycles done, cycles)
        # (arrival time, q, steps, pose) of commands not taken yet, oldest first
        self._pending: deque[tuple] = deque(maxlen=self.PENDING)
        self._pose: Optional[np.ndarray] = None      # the taken servo_p target's pose
        self._filter = servo_filter
        if servo_filter is not None:
            servo_filter.reset(q)
        self._lock = threading.Lock()

    def set(self, q: np.ndarray, pose: Optional[np.ndarray] = None) -> None:
        """Go to ``q`` (rad) in the cycle after this one; ``pose`` (4x4, m): the servo_p target
        ``q`` solves (a Cartesian filter reads it)."""
        self._command(q, 1, pose)

    def ramp(self, q: np.ndarray, steps: int) -> None:
        """Go to ``q`` (rad) over ``steps`` cycles from the one after this one."""
        self._command(q, steps, None)

    def _command(self, q: np.ndarray, steps: int, pose: Optional[np.ndarray]) -> None:
        with self._lock:    # stamped under the lock: the queue stays in arrival order
            self._pending.append((self._cycles.arrival_time(), q.copy(), steps, pose))

    def hold(self, q: np.ndarray) -> None:
        """Hold ``q`` (rad) from the next choice on, whenever this arrives, and drop the
        commands not taken yet: a stop does not wait for a cycle boundary (nor for a filter:
        it starts again from ``q``)."""
        with self._lock:
            self._pending.clear()
            self._ramp = None
            self.target = q.copy()
            self._pose = None
            if self._filter is not None:
                self._filter.reset(q)

    @property
    def goal(self) -> np.ndarray:
        """Where the servo target ends up (rad): the latest command's target, or the end of
        a ramp under way, or the target."""
        with self._lock:
            if self._pending:
                return self._pending[-1][1].copy()
            return (self._ramp[1] if self._ramp is not None else self.target).copy()

    @property
    def latest(self) -> np.ndarray:
        """The latest command's target (rad), taken or not: what the next command is a step
        from."""
        with self._lock:
            return (self._pending[-1][1] if self._pending else self.target).copy()

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        with self._lock:
            end = self._cycles.cycle_end
            while self._pending and self._pending[0][0] <= end:
                _, q, steps, pose = self._pending.popleft()
                self._ramp = None if steps <= 1 else (self.target.copy(), q, 0, steps)
                self._pose = pose if steps <= 1 else None
                if steps <= 1:
                    self.target = q
            if self._ramp is not None:
                start, end_q, k, n = self._ramp
                k += 1
                self.target = start + (end_q - start) * (k / n)
                self._ramp = None if k >= n else (start, end_q, k, n)
            target = self.target
            if self._filter is not None:
                target = self._filter.next(target, self._pose)
        self.moving = bool(np.any(target != q_sp))
        return target


class Jog(Motion):
    """Continuous jog: ramp the speed of one axis up to ``speed`` and hold it until told to
    stop, then ramp down (the ramp: :class:`~jaka_driver.motion.jog.JogVelocity`).
    ``step(q_sp, displacement)`` maps an axis displacement to the next joint setpoint (identity
    on one joint, or Cartesian + IK); it returns None when the move cannot continue (joint
    limit, no IK), which ends the jog at once. ``label`` (coord, axis, direction): a jog call
    for the same axis continues it."""

    def __init__(self, speed: float, accel: float, cycle: float,
                 step: Callable[[np.ndarray, float], Optional[np.ndarray]], label: tuple):
        self.ramp = JogVelocity(accel)       # rad/s or m/s along the axis; rad/s² or m/s²
        self.ramp.command(speed)
        self.cycle = cycle                   # s
        self.step = step
        self.label = label
        self.stop_reason: Optional[str] = None

    def command(self, speed: float) -> None:
        """Ramp to ``speed`` (≥ 0) instead: the same axis jogged again."""
        self.ramp.command(speed)

    def stop(self) -> None:
        self.ramp.stop()

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        v = self.ramp.update(self.cycle)
        if self.ramp.at_rest:
            self.active = self.moving = False
            return q_sp
        q = self.step(q_sp, v * self.cycle)
        if q is None:
            self.stop_reason = "limit"
            self.active = self.moving = False
            return q_sp
        return q


class TwistRun(Motion):
    """A velocity jog (:class:`~jaka_driver.motion.velocity_jog.VelocityJog`): the setpoint
    follows the commanded twist each cycle; inactive once stopped and at rest."""

    def __init__(self, jog: VelocityJog):
        self.jog = jog

    def command(self, twist: np.ndarray) -> None:
        self.jog.command(twist)

    def stop(self) -> None:
        self.jog.stop()

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        q = self.jog.next(q_sp)
        if self.jog.at_rest:
            self.active = self.moving = False
        return q


def servo_target(motion: Motion) -> Optional[ServoTarget]:
    """``motion`` if it is servo mode's source (the one running), else None."""
    return motion if isinstance(motion, ServoTarget) else None


def stopped(reason: str) -> Result:
    return Result.failure(Code.MOTION_STOPPED, reason)
