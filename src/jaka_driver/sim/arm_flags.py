"""The flags the twin's controller reports of its arm — power, enable, servo and drag mode, the
emergency stop, a protective stop or collision and its message — written here and nowhere else.

Each flag changes by a named event (power off, an e-stop pressed, a collision, clear_error,
...), and the event does to the arm what a controller does at that moment: it halts the motion
that runs (the physics loop's one slot, :attr:`~.physics.PhysicsLoop.motion`, whose waiter is
told why) and, when power or enable goes, closes the drives a drag released. Both the backend's
requests and the twin's faults (:class:`~.twin.SimTwin`) go through these events; everybody
else only reads the flags (:class:`ArmFlags`' attributes).

``lock`` is the twin controller's lock: requests change the flags under it, and the backend
decides which motion source runs under it too (a mode and the motion it allows are read
together). The physics thread's own faults (a collision, an overload) never wait for it: it
holds the physics lock then, which a request holding ``lock`` may be waiting for; each flag is
one attribute, so no two writers lose each other's flag.
"""
from __future__ import annotations

import threading

from .motions import stopped
from .physics import PhysicsLoop


class ArmFlags:
    """The twin's flags (see the module), and what each change does to the arm on
    ``physics``. A fresh twin is powered and enabled, with no mode and no error."""

    def __init__(self, physics: PhysicsLoop):
        self.lock = threading.RLock()
        self._physics = physics
        self.reset()

    def reset(self) -> None:
        """A fresh twin's flags: powered, enabled, no mode, no error."""
        with self.lock:
            self.powered = self.enabled = True
            self.servo_mode = self.drag_mode = False
            self.emergency_stop = self.protective_stop = self.collision = False
            self.error_code, self.error_message = 0, ""

    # ---- power ----------------------------------------------------------------------------
    def power(self, on: bool) -> None:
        """Power on, or off: the arm halts on its drives where it is; enable, servo and drag
        mode end."""
        with self.lock:
            if not on:
                self._halt("stopped: power off")
                self.enabled = self.servo_mode = self.drag_mode = False
                self._physics.servo.released = False      # the drives hold what drag let go
            self.powered = on

    def enable(self, on: bool) -> None:
        """Enable, or disable: the arm halts where it is; servo and drag mode end."""
        with self.lock:
            if not on:
                self._halt("stopped: robot disabled")
                self.servo_mode = self.drag_mode = False
                self._physics.servo.released = False
            self.enabled = on

    def _halt(self, reason: str) -> None:
        """Halt within one cycle where the arm is; tell a waiting move why."""
        self._physics.hold_here().abort(stopped(reason))

    # ---- modes (the backend has decided the motion source that goes with them) -------------
    def set_servo_mode(self, on: bool) -> None:
        with self.lock:
            self.servo_mode = on

    def set_drag_mode(self, on: bool) -> None:
        with self.lock:
            self.drag_mode = on

    # ---- faults -----------------------------------------------------------------------------
    def press_emergency_stop(self) -> None:
        """The red button: power is cut, the arm halts, servo and drag mode end."""
        with self.lock:
            self.emergency_stop = True
            self._physics.servo.released = False
            self._halt("stopped: emergency stop")
            self.powered = self.enabled = self.servo_mode = self.drag_mode = False

    def release_emergency_stop(self) -> None:
        with self.lock:
            self.emergency_stop = False

    def trigger_protective_stop(self, reason: str) -> None:
        """A protective stop (injected): the arm halts where it is; servo mode ends."""
        with self.lock:
            self.protective_stop = True
            self.error_message = reason
            self._halt(reason)
            self.servo_mode = False

    def collided(self, message: str) -> None:
        """A contact above the collision level (physics thread, inside a cycle's checks).

        Contacts are checked once per 8 ms cycle, so the force is seen over the threshold up
        to a cycle after it crossed it; the arm is held where it stood at the end of the
        previous cycle, whose contacts were below the threshold, so it does not stay pressed
        into the obstacle (up to ~2 mm back at a 0.3 m/s swing)."""
        self.collision = True
        self.error_message = message
        physics = self._physics
        physics.hold_at(physics.checked_pose()).abort(stopped(message))
        self.servo_mode = False

    def overloaded(self, message: str) -> None:
        """A drive that cannot hold (physics thread): a protective stop on the brakes."""
        self.protective_stop = True
        self.error_message = message
        self._physics.engage_brakes().abort(stopped(message))
        self.servo_mode = False

    def force_stopped(self, message: str) -> None:
        """The force/torque sensor's soft limit or the compliance condition exceeded (physics
        thread): a protective stop where the arm is, held by its drives (no brakes: the arm is
        sound, it pressed too hard), as a controller's force stop."""
        self.protective_stop = True
        self.error_message = message
        self._physics.hold_here().abort(stopped(message))
        self.servo_mode = False

    def clear(self) -> list[str]:
        """clear_error: the collision, protective stop and error cleared; returns the names of
        those that stood."""
        with self.lock:
            was = [name for name, flag in (("collision", self.collision),
                                           ("protective stop", self.protective_stop),
                                           ("error", self.error_code != 0)) if flag]
            self.collision = self.protective_stop = False
            self.error_code, self.error_message = 0, ""
            return was
