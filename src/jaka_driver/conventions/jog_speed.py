"""Which field of a jog request is its speed: the interface document says ``mvvelo``; JAKA's
driver code reads ``mvacc`` (for every coord_mode, joint rad/s or Cartesian mm/s).

``document`` conventions read ``mvvelo`` and, when it is 0 and ``mvacc`` is not, ``mvacc``
(noted), so programs written either way jog. ``jaka_code`` conventions read ``mvacc`` only, as
JAKA's code does: ``mvvelo`` is not looked at.
"""
from __future__ import annotations

from ..common.results import CommandRefused
from .choice import Conventions


def jog_speed_field(conventions: Conventions, mvvelo: float, mvacc: float,
                    notes: list[str]) -> tuple[str, float]:
    """(field name, its value in the request's unit) of the jog speed, not yet checked; a note
    in ``notes`` when ``document`` conventions fall back to mvacc."""
    if conventions.jog_speed_field == "mvacc":
        return "mvacc", float(mvacc)
    speed = float(mvvelo)
    if speed == 0 and float(mvacc) > 0:
        notes.append("mvvelo is 0: using mvacc as the speed, like JAKA's driver")
        return "mvacc", float(mvacc)
    return "mvvelo", speed


def explained(refusal: CommandRefused, conventions: Conventions) -> CommandRefused:
    """A refused jog speed, with where the speed was read from under ``jaka_code``."""
    if conventions.jog_speed_field != "mvacc":
        return refusal
    result = refusal.result()
    return CommandRefused(result.code, f"{result.message} (conventions {conventions.name}: the "
                          "jog speed is mvacc, as JAKA's driver code reads it)")
