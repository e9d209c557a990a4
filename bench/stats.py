"""Small statistics on samples: percentiles and the summaries the report prints."""
from __future__ import annotations

import numpy as np


def percentiles(values, qs=(50, 99)) -> list[float]:
    """Percentiles ``qs`` (0–100) of ``values`` (linear interpolation); NaNs if empty."""
    a = np.asarray(values, float)
    if a.size == 0:
        return [float("nan")] * len(qs)
    return [float(v) for v in np.percentile(a, qs)]


def summary(values, scale: float = 1.0) -> dict:
    """``{n, p50, p99, max, mean}`` of ``values`` times ``scale`` (e.g. 1e3 for s → ms)."""
    a = np.asarray(values, float) * scale
    if a.size == 0:
        return {"n": 0, "p50": None, "p99": None, "max": None, "mean": None}
    p50, p99 = percentiles(a)
    return {"n": int(a.size), "p50": p50, "p99": p99, "max": float(a.max()),
            "mean": float(a.mean())}


def fmt(value, digits: int = 2) -> str:
    """A number for the table; ``—`` for a missing one."""
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "—"
    return f"{value:.{digits}f}"
