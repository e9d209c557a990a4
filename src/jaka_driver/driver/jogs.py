"""Jogs through the door: the continuous jog (kept alive by calling again; the door's jog
watchdog stops it ``jog_timeout`` s after the last call) and the velocity jog (a twist followed
until twists stop coming: the twist watchdog stops it ``twist_timeout`` s after the last).
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..common.results import Code, CommandRefused, Result
from ..conventions.jog_speed import explained, jog_speed_field
from . import checks as check
from .door import RequestPart, answers, with_notes


class JogRequests(RequestPart):
    """The jog and the velocity jog (see the module)."""

    @answers
    def jog(self, coord_mode: int, index: int, mvvelo: float, mvacc: float = 0.0) -> Result:
        """Continuous jog (docs/interface.md, "jog"): coord 0 joint / 1 base / 2 tool; index
        0–11, odd = negative; speed ``mvvelo`` (rad/s, or mm/s for X–Z; ``mvacc`` with
        ``jaka_code`` conventions). Kept alive by calling again."""
        coord = check.integer_in("coord_mode", coord_mode, 0, 2)
        idx = check.integer_in("index", index, 0, 11)
        axis, direction = idx // 2, (-1 if idx % 2 else 1)
        notes: list[str] = []
        name, raw = jog_speed_field(self.conventions, mvvelo, mvacc, notes)
        try:
            label, unit, speed = check.jog_speed(self.model, coord, axis, name, raw, notes)
        except CommandRefused as refusal:
            raise explained(refusal, self.conventions) from None
        door = self.door
        door.no_blocking_move("jog")
        if door.twist.session is not None:
            raise CommandRefused(Code.BUSY, "jog refused: a velocity jog is running")
        door.ready()
        session = door.jog.session
        same = session is not None and (session.coord, session.index) == (coord, idx)
        result = self.backend.jog(coord, axis, direction, speed)
        if not result.ok:
            door.jog.clear()
            return result
        door.jog.kick(coord, idx, speed)
        sign = "+" if direction > 0 else "-"
        what = "still jogging" if same else "jogging"
        shown = speed * 1000 if unit == "mm/s" else speed
        return with_notes(Result.success(f"{what} {label}{sign} at {shown:g} {unit} "
                                         f"(stops {door.jog.timeout:g} s after the last call)"),
                          notes)

    @answers(react=False)
    def velocity_jog(self, linear: Sequence[float], angular: Sequence[float],
                     in_tool: bool) -> Result:
        """Follow the twist ``linear`` (m/s) + ``angular`` (rad/s), in the base frame or the
        tool frame (``in_tool``), until twists stop coming (the twist watchdog: ``twist_timeout``
        s after the last, the arm ramps to rest). Speeds are checked as jog's: the TCP's at
        most the model's, the rotation's at most the tool rotation cap."""
        v = check.vector("twist.linear", linear, 3)
        w = check.vector("twist.angular", angular, 3)
        check.twist_speeds(self.model, v, w)
        door = self.door
        door.no_blocking_move("velocity jog")
        if door.jog.session is not None:
            raise CommandRefused(Code.BUSY, "velocity jog refused: a jog is running")
        # a controller follows the twist in servo mode (controller/twist_stream.py), entered
        # by the jog's first twist: the next ones find it on
        door.ready(allow_servo_mode=door.twist.session is not None)
        result = self.backend.velocity_jog(np.concatenate([v, w]), bool(in_tool))
        if not result.ok:
            door.twist.clear()
            return result
        door.twist.kick(2 if in_tool else 1, -1, math.hypot(*v.tolist()))
        return result
