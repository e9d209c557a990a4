"""Velocity ramp of a continuous jog: accelerate to the commanded jog speed, hold it, and
slow down smoothly when the command drops (to 0 to stop, or to the other sign to reverse).

Unit-agnostic: speed in rad/s (joint or rotation jog) or m/s (translation), acceleration in
the same unit per second, time s.
"""
from __future__ import annotations

import math


class JogVelocity:
    """Current jog speed, moved towards the commanded one by at most ``accel · dt`` per
    update. Signed: the sign is the jog direction.

    >>> ramp = JogVelocity(accel=2.0)
    >>> ramp.command(1.0)
    >>> ramp.update(0.25)
    0.5
    """

    def __init__(self, accel: float, speed: float = 0.0):
        accel = float(accel)
        if not math.isfinite(accel) or accel <= 0.0:
            raise ValueError(f"accel is {accel:g}, expected a finite value > 0")
        self.accel = accel
        self.speed = float(speed)      # current
        self.target = float(speed)     # commanded

    def command(self, speed: float) -> None:
        """Set the speed to ramp to (0 to stop)."""
        speed = float(speed)
        if not math.isfinite(speed):
            raise ValueError(f"jog speed is {speed:g}, expected a finite value")
        self.target = speed

    def stop(self) -> None:
        self.target = 0.0

    def update(self, dt: float) -> float:
        """Advance ``dt`` s and return the current speed."""
        step = self.accel * float(dt)
        gap = self.target - self.speed
        self.speed = self.target if abs(gap) <= step else self.speed + math.copysign(step, gap)
        return self.speed

    @property
    def at_rest(self) -> bool:
        """Stopped and not commanded to move."""
        return self.speed == 0.0 and self.target == 0.0

    @property
    def stopping_distance(self) -> float:
        """Distance (≥ 0) the ramp still covers if stopped now: v² / (2 a)."""
        return self.speed * self.speed / (2.0 * self.accel)
