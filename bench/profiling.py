"""Where the time goes: a cProfile summary to put in the report next to a missed target."""
from __future__ import annotations

import cProfile
import pstats
from typing import Callable


def hot_functions(work: Callable[[], None], calls: int, top: int = 4) -> list[tuple[str, float]]:
    """Run ``work()`` ``calls`` times under cProfile; the ``top`` functions by own time
    (``tottime``) as ``(name, % of all own time)``. cProfile slows Python code more than C
    calls, so the shares are a guide, not a measurement."""
    prof = cProfile.Profile()
    prof.enable()
    for _ in range(calls):
        work()
    prof.disable()
    stats = pstats.Stats(prof).stats
    total = sum(v[2] for v in stats.values()) or 1.0
    ranked = sorted(((fn, tt) for (_path, _line, fn), (_cc, _nc, tt, _ct, _callers)
                     in stats.items()), key=lambda r: -r[1])
    return [(name, 100.0 * tt / total) for name, tt in ranked[:top]]


def describe(hot: list[tuple[str, float]]) -> str:
    return ", ".join(f"{name} {share:.0f} %" for name, share in hot)
