"""The flags the twin's controller reports of its arm — power, enable, servo and drag mode, the
emergency stop, a protective stop or collision and its message — written here and nowhere else.

Each flag changes by a named event (power off, an e-stop pressed, a collision, clear_error,
...), and the event does to the arm what a controller does at that moment: it halts the motion
that runs (the physics loop's one slot, :attr:`~.physics.PhysicsLoop.motion`, whose waiter is
told why) and, when power or enable goes, closes the drives a drag released. Both the backend's requests and the twin's
faults (:class:`~.twin.SimTwin`) go through these events; readers take :attr:`ArmFlags.now`,
one consistent :class:`Flags`, in a sample.

``lock`` is the twin controller's lock: requests change the flags under it, and the backend
decides which motion source runs under it too (a mode and the motion it allows are read
together). The physics thread's own faults (a collision, an overload) never wait for it: it
holds the physics lock then, which a request holding ``lock`` may be waiting for. Each change of
:attr:`ArmFlags.now` is one short step of its own, so no two writers lose each other's flag.
"""
from __future__ import annotations

import threading
from typing import NamedTuple

from .motions import stopped
from .physics import PhysicsLoop


class Flags(NamedTuple):
    """The arm's flags at one moment (those of a fresh twin by default: powered, enabled)."""

    powered: bool = True
    enabled: bool = True
    servo_mode: bool = False
    drag_mode: bool = False
    emergency_stop: bool = False
    protective_stop: bool = False
    collision: bool = False
    error_code: int = 0
    error_message: str = ""


class ArmFlags:
    """The twin's flags (see the module), and what each change does to the arm on
    ``physics``."""

    def __init__(self, physics: PhysicsLoop):
        self.lock = threading.RLock()
        self._write = threading.Lock()      # one change of ``now`` at a time (nothing inside)
        self._physics = physics
        #: the flags as they stand (replaced whole at each change: a reader sees one moment)
        self.now = Flags()

    def _set(self, **changes) -> None:
        with self._write:
            self.now = self.now._replace(**changes)

    def reset(self) -> None:
        """A fresh twin's flags: powered, enabled, no mode, no error."""
        with self._write:
            self.now = Flags()

    # ---- power ----------------------------------------------------------------------------
    def power(self, on: bool) -> None:
        """Power on, or off: the arm halts on its drives where it is; enable, servo and drag
        mode end."""
        with self.lock:
            if not on:
                self._halt("stopped: power off")
                self._set(enabled=False, servo_mode=False, drag_mode=False)
                self._physics.servo.released = False      # the drives hold what drag let go
            self._set(powered=on)

    def enable(self, on: bool) -> None:
        """Enable, or disable: the arm halts where it is; servo and drag mode end."""
        with self.lock:
            if not on:
                self._halt("stopped: robot disabled")
                self._set(servo_mode=False, drag_mode=False)
                self._physics.servo.released = False
            self._set(enabled=on)

    def _halt(self, reason: str) -> None:
        """Halt within one cycle where the arm is; tell a waiting move why."""
        self._physics.hold_here().abort(stopped(reason))

    # ---- modes (the backend has decided the motion source that goes with them) -------------
    def servo_mode(self, on: bool) -> None:
        with self.lock:
            self._set(servo_mode=on)

    def drag_mode(self, on: bool) -> None:
        with self.lock:
            self._set(drag_mode=on)

    # ---- faults -----------------------------------------------------------------------------
    def press_emergency_stop(self) -> None:
        """The red button: power is cut, the arm halts, servo and drag mode end."""
        with self.lock:
            self._set(emergency_stop=True)
            self._physics.servo.released = False
            self._halt("stopped: emergency stop")
            self._set(powered=False, enabled=False, servo_mode=False, drag_mode=False)

    def release_emergency_stop(self) -> None:
        with self.lock:
            self._set(emergency_stop=False)

    def protective_stop(self, reason: str) -> None:
        """A protective stop (injected): the arm halts where it is; servo mode ends."""
        with self.lock:
            self._set(protective_stop=True, error_message=reason)
            self._halt(reason)
            self._set(servo_mode=False)

    def collided(self, message: str) -> None:
        """A contact above the collision level (physics thread, inside a cycle's checks).

        Contacts are checked once per 8 ms cycle, so the force is seen over the threshold up
        to a cycle after it crossed it; the arm is held where it stood at the end of the
        previous cycle, whose contacts were below the threshold, so it does not stay pressed
        into the obstacle (up to ~2 mm back at a 0.3 m/s swing)."""
        self._set(collision=True, error_message=message)
        physics = self._physics
        physics.hold_at(physics.checked_pose()).abort(stopped(message))
        self._set(servo_mode=False)

    def overloaded(self, message: str) -> None:
        """A drive that cannot hold (physics thread): a protective stop on the brakes."""
        self._set(protective_stop=True, error_message=message)
        self._physics.engage_brakes().abort(stopped(message))
        self._set(servo_mode=False)

    def clear(self) -> list[str]:
        """clear_error: the collision, protective stop and error cleared; returns the names of
        those that stood."""
        with self._write:
            f = self.now
            was = [name for name, flag in (("collision", f.collision),
                                           ("protective stop", f.protective_stop),
                                           ("error", f.error_code != 0)) if flag]
            self.now = f._replace(collision=False, protective_stop=False, error_code=0,
                                  error_message="")
            return was
