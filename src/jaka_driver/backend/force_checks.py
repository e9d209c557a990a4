"""The value checks of force requests, in one place below the driver's door and the emulator,
which both apply them (a controller's ranges are the arm's: its sensor's range from the arm's
configuration): each raises :class:`CommandRefused` (-2) naming the field, the value and the
limit, and returns the value in the facet's units (:mod:`.force`'s: SI, and a rebound as requests give it).

Request units: N and N·m; ``rebound`` N/mm on x y z and N·m/rad on rx ry rz (a stiffness in
the request's length unit, as payload centroids are mm); the sensor's payload kg at a centroid
in mm; filter Hz; joints rad; push durations s. Limits: the sensor's ``range`` (its largest
reading, from the arm's configuration) bounds every force a request may set.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from ..common import values as check
from ..common.models import RobotModel
from ..common.results import invalid
from .force import AXES, WRENCH_NAMES, AdmittanceAxis, ToolDriveAxis, VelocityCompliance

#: Hz, the highest cut-off of the sensor filter (above it the filter would do nothing at the
#: 8 ms cycle force control runs at)
FILTER_MAX_HZ = 100.0
#: the stiffest rebound a request may set: N/mm on x y z, N·m/rad on rx ry rz
REBOUND_MAX = (20.0, 20.0, 20.0, 200.0, 200.0, 200.0)
#: the most poses one identification moves through
MAX_POSES = 20
#: a push on the twin's tool: at most this force (N) and moment (N·m), this long (s)
PUSH_FORCE_MAX = 500.0
PUSH_MOMENT_MAX = 50.0
PUSH_DURATION_MAX = 60.0
_UNITS = ("N", "N", "N", "N·m", "N·m", "N·m")


def axis(value: int) -> int:
    """An axis of force control: 0–5 (x y z rx ry rz)."""
    return check.integer_in("axis", value, 0, 5)


def frame(name: str, value: int) -> int:
    """A force-control frame: 0 tool, 1 base (world)."""
    return check.integer_in(name, value, 0, 1)


def wrench_limits(name: str, values: Sequence[float], sensor_range: np.ndarray, *,
                  zero_allowed: bool) -> np.ndarray:
    """Six limits (N, N·m), each within the sensor's range; 0 only where ``zero_allowed``
    (the compliance condition: 0 = not checked)."""
    w = check.vector(name, values)
    for i, v in enumerate(w):
        low_ok = v >= 0 if zero_allowed else v > 0
        if not low_ok or v > sensor_range[i]:
            low = "0" if zero_allowed else "> 0"
            raise invalid(f"{name} {WRENCH_NAMES[i]} is {v:g} {_UNITS[i]}, expected {low} to "
                          f"{sensor_range[i]:g} {_UNITS[i]} (the sensor's range)")
    return w


def _rebound(i: int, value: float, enabled: bool = True) -> float:
    """A rebound (N/mm or N·m/rad, the facet's unit too); its range is checked on an enabled
    axis."""
    unit = "N/mm" if i < 3 else "N·m/rad"
    r = check.finite("rebound", value, unit)
    if enabled and not 0.0 <= r <= REBOUND_MAX[i]:
        raise invalid(f"rebound on {AXES[i]} is {r:g} {unit}, expected 0–{REBOUND_MAX[i]:g} "
                      f"{unit}")
    return r


def _stiffness(name: str, i: int, value: float, sensor_range: np.ndarray) -> float:
    v = check.finite(name, value, _UNITS[i])
    if not 0.0 < v <= sensor_range[i]:
        raise invalid(f"{name} on {AXES[i]} is {v:g} {_UNITS[i]}, expected > 0 and at most "
                      f"{sensor_range[i]:g} {_UNITS[i]} (the sensor's range): the wrench that "
                      "moves the axis at the compliant speed")
    return v


def admittance(i: int, opt: int, ft_user: float, rebound: float, constant: float,
               normal_track: int, sensor_range: np.ndarray) -> AdmittanceAxis:
    """Axis ``i`` of admittance (JAKA's set_admit_ctrl_config). A disabled axis keeps its
    values, checked only for being numbers."""
    enabled = bool(check.integer_in("opt", opt, 0, 1))
    if check.integer_in("normal_track", normal_track, 0, 1):
        raise invalid("normal_track is 1, expected 0: JAKA's SDK deprecates normal tracking "
                      "(always disabled since SDK 2.1.12); use the constant force of the axis")
    c = check.finite("ft_constant", constant, _UNITS[i])
    if abs(c) > sensor_range[i]:
        raise invalid(f"ft_constant on {AXES[i]} is {c:g} {_UNITS[i]}, beyond the sensor's "
                      f"range ±{sensor_range[i]:g} {_UNITS[i]}")
    if not enabled:
        return AdmittanceAxis(False, check.finite("ft_user", ft_user),
                              _rebound(i, rebound, False), c, False)
    return AdmittanceAxis(True, _stiffness("ft_user", i, ft_user, sensor_range),
                          _rebound(i, rebound), c, False)


def tool_drive(i: int, opt: int, rigidity: float, rebound: float,
               sensor_range: np.ndarray) -> ToolDriveAxis:
    """Axis ``i`` of tool drive (JAKA's set_tool_drive_config)."""
    enabled = bool(check.integer_in("opt", opt, 0, 1))
    if not enabled:
        return ToolDriveAxis(False, check.finite("rigidity", rigidity),
                             _rebound(i, rebound, False))
    return ToolDriveAxis(True, _stiffness("rigidity", i, rigidity, sensor_range),
                         _rebound(i, rebound))


def velocity_compliance(level: int, rates: Sequence[float]) -> VelocityCompliance:
    """JAKA's VelCom: ``level`` 1–3 sets ``level`` + 1 rates, 1 > rate1 > … > 0; the others
    must be 0."""
    n = check.integer_in("level", level, 1, 3)
    r = check.vector("rates", rates, 4)
    used, unused = r[:n + 1], r[n + 1:]
    previous = 1.0
    for k, v in enumerate(used):
        if not 0.0 < v < previous:
            raise invalid(f"rates[{k}] is {v:g}, expected 0 < rate < {previous:g} (level {n} "
                          f"uses {n + 1} rates, each below the one before, 1 > rate1 > … > 0)")
        previous = v
    if np.any(unused != 0.0):
        raise invalid(f"rates[{n + 1}:] are {unused.tolist()}, expected 0 (level {n} uses "
                      f"{n + 1} rates)")
    return VelocityCompliance(n, tuple(float(v) for v in r))


def filter_hz(value: float) -> float:
    hz = check.finite("cutoff", value, "Hz")
    if not 0.0 <= hz <= FILTER_MAX_HZ:
        raise invalid(f"cutoff is {hz:g} Hz, expected 0 (off) to {FILTER_MAX_HZ:g} Hz")
    return hz


def identification_poses(values: Sequence[float], model: RobotModel) -> list[np.ndarray]:
    """Joint positions (rad), six per pose, 1–:data:`MAX_POSES` poses, inside the limits."""
    flat = list(values)
    if not flat or len(flat) % 6:
        raise invalid(f"joint_positions has {len(flat)} values, expected 6 per pose "
                      f"(1–{MAX_POSES} poses)")
    if len(flat) // 6 > MAX_POSES:
        raise invalid(f"joint_positions has {len(flat) // 6} poses, limit {MAX_POSES}")
    return [check.joint_targets(f"pose {k + 1}", flat[6 * k:6 * k + 6], model)
            for k in range(len(flat) // 6)]


def push(wrench: Sequence[float], duration: float) -> tuple[np.ndarray, float]:
    """A push on the twin's tool: (wrench N and N·m, duration s)."""
    w = check.vector("wrench", wrench)
    f, m = float(np.linalg.norm(w[:3])), float(np.linalg.norm(w[3:]))
    if f > PUSH_FORCE_MAX:
        raise invalid(f"wrench force is {f:.1f} N, limit {PUSH_FORCE_MAX:g} N")
    if m > PUSH_MOMENT_MAX:
        raise invalid(f"wrench moment is {m:.1f} N·m, limit {PUSH_MOMENT_MAX:g} N·m")
    t = check.finite("duration", duration, "s")
    if not 0.0 <= t <= PUSH_DURATION_MAX:
        raise invalid(f"duration is {t:g} s, expected 0 (let go) to {PUSH_DURATION_MAX:g} s")
    return w, t
