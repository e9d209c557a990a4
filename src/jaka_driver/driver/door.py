"""The door's core: what every request part of :class:`~.robot_driver.RobotDriver` shares.

:class:`Door` holds the backend and what decides whether the arm may be moved now: the motion
lock (one blocking move at a time), the jog and velocity-jog watchdogs, the servo stream's
bookkeeping, and the state checks in their fixed order (:meth:`Door.ready`). :class:`RequestPart`
is the base of the parts that serve the requests by subject (moves, jogs, servo, programs,
settings, the twin's own), each handed the door at construction and using nothing else of the
driver. :func:`answers` is the wrapper every request method wears: a refusal becomes its
:class:`Result`, any other exception a -3 answer, and in simulated time the request acts
between two cycles.
"""
from __future__ import annotations

import logging
import threading
from contextlib import contextmanager
from typing import Callable

from ..backend import Backend
from ..backend.robot_state import RobotState
from ..common.results import Code, CommandRefused, Result
from ..conventions import Conventions
from .watchdogs import JogWatchdog, ServoStream

log = logging.getLogger(__name__)


def answers(method: Callable | None = None, *, react: bool = True) -> Callable:
    """Turn a refusal into its Result and any other exception into a -3 answer: a request may
    be refused, but it never takes the driver down. Simulated time stands still while a
    request is in the driver (jaka_driver.backend.clock): it acts at the sim time it arrived.
    ``react=False`` for requests a client streams once per cycle (servo_j, servo_p): their
    reply does not keep time waiting for the next call (the twin's clock waits for the next
    target instead). Use as ``@answers`` or ``@answers(react=False)`` on a method of an object
    with a ``clock``."""
    if method is None:
        return lambda m: answers(m, react=react)

    def wrapper(self, *args, **kwargs) -> Result:
        try:
            with self.clock.hold(react=react):
                return method(self, *args, **kwargs)
        except CommandRefused as refusal:
            return refusal.result()
        except Exception as exc:  # noqa: BLE001 — the node must survive any request
            log.exception("%s failed", method.__name__)
            return Result.failure(Code.COMMUNICATION_ERROR,
                                  f"{method.__name__} failed inside the driver: {exc!r}")

    wrapper.__name__ = method.__name__
    wrapper.__doc__ = method.__doc__
    return wrapper


class Door:
    """The backend and who may move the arm now (see the module). Timeouts, s of the
    backend's clock: ``jog_timeout`` after a jog's last call it stops, ``servo_timeout`` without
    a servo target the stream counts as stopped, ``twist_timeout`` after the last twist a
    velocity jog stops."""

    def __init__(self, backend: Backend, conventions: Conventions, *, jog_timeout: float,
                 servo_timeout: float, twist_timeout: float):
        self.backend = backend
        self.model = backend.model
        #: every timeout runs on the backend's time (wall, or the twin's sim time)
        self.clock = backend.clock
        self.conventions = conventions
        self.move_lock = threading.Lock()     # one blocking move at a time
        self.jog = JogWatchdog(self._jog_expired, timeout=jog_timeout, clock=self.clock)
        self.twist = JogWatchdog(self._twist_expired, timeout=twist_timeout, clock=self.clock)
        self.servo = ServoStream(timeout=servo_timeout, clock=self.clock)

    def close(self) -> None:
        self.jog.close()
        self.twist.close()

    # ---- the state machine: may the arm move now? ----------------------------------------
    def ready(self, *, servo: bool = False, allow_servo_mode: bool = False,
              program_step: bool = False) -> RobotState:
        """The arm may move: connected, no e-stop, powered, enabled, no error, right mode, and
        no program running or paused (unless this is a step of that program)."""
        st = self.backend.state()
        if not st.connected:
            raise CommandRefused(Code.NOT_CONNECTED, "not connected to the controller")
        if st.emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed")
        if not st.powered:
            raise CommandRefused(Code.NOT_POWERED, "robot is not powered (call power)")
        if not st.enabled:
            raise CommandRefused(Code.NOT_ENABLED, "robot is not enabled (call enable)")
        if st.in_error:
            raise CommandRefused(Code.MOTION_STOPPED, f"{error_text(st)} stands; "
                                 "call clear_err before moving")
        if st.drag_mode:
            raise CommandRefused(Code.WRONG_MODE, "refused in drag mode")
        if servo and not st.servo_mode:
            raise CommandRefused(Code.SERVO_MODE_OFF, "servo mode is off (call servo_move_enable)")
        if not servo and not allow_servo_mode and st.servo_mode:
            raise CommandRefused(Code.WRONG_MODE, "refused in servo mode "
                                 "(leave it with servo_move_enable false)")
        if st.program_state and not program_step:
            raise CommandRefused(Code.BUSY, "a program is running or paused (program/stop "
                                 "ends it)")
        return st

    def not_jogging(self) -> None:
        if self.jog.session is not None:
            raise CommandRefused(Code.BUSY, "a jog is running (stop_move, or wait 3 s after "
                                 "the last jog call)")
        if self.twist.session is not None:
            raise CommandRefused(Code.BUSY, "a velocity jog is running (stop_move, or stop "
                                 f"sending twists: it stops {self.twist.timeout:g} s after "
                                 "the last)")

    def no_blocking_move(self, what: str) -> None:
        if self.move_lock.locked():
            raise CommandRefused(Code.BUSY, f"{what} refused: a blocking move is running")

    @contextmanager
    def blocking_move(self, what: str):
        if not self.move_lock.acquire(blocking=False):
            raise CommandRefused(Code.BUSY, f"{what} refused: another move is running")
        try:
            yield
        finally:
            self.move_lock.release()

    @property
    def moving(self) -> bool:
        return (self.move_lock.locked() or self.jog.session is not None
                or self.twist.session is not None)

    def forget_jogs(self) -> None:
        """No jog or velocity jog is kept alive any more (a stop, power off, a reset)."""
        self.jog.clear()
        self.twist.clear()

    def ratio(self) -> float:
        """The speed ratio moves are planned at (time × 1/r), 1 when the backend's is odd."""
        ratio = float(self.backend.speed_ratio())
        return ratio if 0.0 < ratio <= 1.0 else 1.0

    def _jog_expired(self) -> None:
        log.info("jog stopped: no jog call for %.1f s", self.jog.timeout)
        self.backend.jog_stop()

    def _twist_expired(self) -> None:
        log.info("velocity jog stopping: no twist for %.2f s", self.twist.timeout)
        self.backend.jog_stop()


def error_text(st: RobotState) -> str:
    """What stops the arm, in words."""
    if st.collision:
        return "collision alarm"
    if st.protective_stop:
        return "protective stop"
    return f"error {st.error_code:#x} {st.error_message}".strip()


class RequestPart:
    """A part of RobotDriver serving the requests of one subject through ``door``."""

    def __init__(self, door: Door):
        self.door = door
        self.backend = door.backend
        self.model = door.model
        self.clock = door.clock
        self.conventions = door.conventions


def note(notes: list[str], text: str | None) -> None:
    if text:
        notes.append(text)


def with_notes(result: Result, notes: list[str]) -> Result:
    if not notes:
        return result
    return Result(result.code, f"{result.message} ({'; '.join(notes)})", result.value)
