"""Which servo filter, with which parameters: JAKA's six (``set_servo_move_filter``,
docs/protocol.md; JAKA's SDK header ``JAKAZuRobot.h`` and JAKA's guide "Setting of Filter in
Servo Mode" describe them), checked against their ranges.

The request's units are the driver's (docs/interface.md, "set_servo_filter"): joint and
rotation limits rad/s, rad/s², rad/s³; Cartesian position limits mm/s, mm/s², mm/s³; the
cut-off Hz; buffers are counts of 8 ms cycles. The spec holds SI (m for positions).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import Dict, Optional, Tuple

from ...common.constants import MAX_TOOL_ROTATION_ACCEL, MAX_TOOL_ROTATION_SPEED, SERVO_CYCLE
from ...common.models import RobotModel
from ...common.results import invalid


class FilterType(IntEnum):
    """JAKA's ``filter_type`` numbers."""

    NONE = 0
    JOINT_LPF = 1            # first-order low-pass, per joint
    JOINT_NLF = 2            # third-order non-linear (velocity, acceleration, jerk), per joint
    JOINT_MMF = 3            # multi-order mean, per joint
    CARTESIAN_NLF = 4        # third-order non-linear on the TCP pose (servo_p only)
    SPEED_FORESIGHT = 5      # mean filter with velocity look-ahead, per joint

    @property
    def word(self) -> str:
        return _WORDS[self]


_WORDS = {FilterType.NONE: "none", FilterType.JOINT_LPF: "joint low-pass",
          FilterType.JOINT_NLF: "joint non-linear", FilterType.JOINT_MMF: "joint multi-order mean",
          FilterType.CARTESIAN_NLF: "Cartesian non-linear",
          FilterType.SPEED_FORESIGHT: "speed foresight"}

#: Hz — the cut-off's range: down to a 16 s time constant, up to the cycle's Nyquist frequency
CUTOFF_HZ = (0.01, 0.5 / SERVO_CYCLE)
#: cycles — a mean filter's buffer (JAKA: under 3 risks planning failure; 200 is the most its
#: own examples use: 1.6 s)
BUFFER = (1, 200)
#: the largest weight of a multi-order mean (only their ratios matter), and the largest
#: foresight ``kp`` (JAKA's examples send 0.03 and 2; above 1 the twin's foresight closes the
#: whole gap to its prediction each cycle, as at 1: it never runs past it)
MAX_WEIGHT = 1000.0
#: jerk limits up to this many times the acceleration limit's range (1/s)
JERK_PER_ACCEL = 1000.0
#: speed and acceleration limits up to 10 × the model's: a limit the arm cannot reach does not
#: bind (a controller accepts it, and JAKA's examples send such), a larger one is taken for a
#: unit mistake (deg for rad, m for mm), as the driver's other speed checks take it
LIMIT_FACTOR = 10.0


@dataclass(frozen=True)
class ServoFilterSpec:
    """A filter and its parameters in SI: ``cutoff`` Hz; ``velocity``/``accel``/``jerk``
    rad/s… (joint NLF, or the Cartesian NLF's rotation); ``linear_velocity``/``_accel``/
    ``_jerk`` m/s… (Cartesian NLF); ``buffer`` cycles; ``kp``/``kv``/``ka`` (the mean filters)."""

    type: FilterType = FilterType.NONE
    cutoff: float = 0.0
    velocity: float = 0.0
    accel: float = 0.0
    jerk: float = 0.0
    linear_velocity: float = 0.0
    linear_accel: float = 0.0
    linear_jerk: float = 0.0
    buffer: int = 0
    kp: float = 0.0
    kv: float = 0.0
    ka: float = 0.0

    def describe(self) -> str:
        """The filter in the request's units, for answers and /diagnostics."""
        t = self.type
        if t == FilterType.JOINT_LPF:
            detail = f"cut-off {self.cutoff:g} Hz"
        elif t == FilterType.JOINT_NLF:
            detail = (f"{self.velocity:g} rad/s, {self.accel:g} rad/s², "
                      f"{self.jerk:g} rad/s³")
        elif t == FilterType.CARTESIAN_NLF:
            detail = (f"{self.linear_velocity * 1e3:g} mm/s, {self.linear_accel * 1e3:g} "
                      f"mm/s², {self.linear_jerk * 1e3:g} mm/s³; {self.velocity:g} rad/s, "
                      f"{self.accel:g} rad/s², {self.jerk:g} rad/s³")
        elif t == FilterType.JOINT_MMF:
            detail = f"buffer {self.buffer}, kp {self.kp:g}, kv {self.kv:g}, ka {self.ka:g}"
        elif t == FilterType.SPEED_FORESIGHT:
            detail = f"buffer {self.buffer}, kp {self.kp:g}"
        else:
            return "none"
        return f"{t.word} ({detail})"


def _in(name: str, value: float, lo: float, hi: float, unit: str, *,
        open_low: bool = True, clamp: bool = False) -> float:
    value = float(value)
    if clamp and math.isfinite(value) and value > hi:
        return hi
    low_ok = value > lo if open_low else value >= lo
    if not (math.isfinite(value) and low_ok and value <= hi):
        bracket = "(" if open_low else "["
        raise invalid(f"{name} is {value:g}{unit}, expected {bracket}{lo:g}, {hi:g}]{unit}")
    return value


def _buffer(value: float, clamp: bool = False) -> int:
    lo, hi = BUFFER
    if clamp and math.isfinite(float(value)) and float(value) == int(value) and value > hi:
        return hi
    if not (math.isfinite(float(value)) and float(value) == int(value) and lo <= value <= hi):
        raise invalid(f"mmf_buffer is {value:g}, expected a whole number {lo}–{hi} (cycles of "
                      f"{SERVO_CYCLE * 1000:g} ms)")
    return int(value)


def checked_spec(model: RobotModel, filter_type: int, params: Dict[str, float], *,
                 clamp: bool = False) -> ServoFilterSpec:
    """The :class:`ServoFilterSpec` a request asks for (``params`` by the request's field
    names: ``lpf_cutoff_hz``, ``nlf_max_vr``/``_ar``/``_jr`` rad/s…, ``nlf_max_vp``/``_ap``/
    ``_jp`` mm/s…, ``mmf_buffer``, ``mmf_kp``/``_kv``/``_ka``; the fields the filter does not
    use are not read), or -2 naming the field, its value and its range.

    ``clamp``: a value above its range is taken as the range's top instead of refused — what
    the twin can run of a request a controller accepts (the emulator: JAKA documents no upper
    bound, and a cut-off above the 8 ms cycle's 62.5 Hz filters no differently on the twin
    than 62.5 Hz does; docs/twin.md, "Servo filters")."""
    try:
        kind = FilterType(int(filter_type))
    except (ValueError, TypeError):
        raise invalid(f"filter_type is {filter_type}, expected 0–5 (0 none, 1 joint low-pass, "
                      "2 joint non-linear, 3 joint multi-order mean, 4 Cartesian non-linear, "
                      "5 speed foresight)") from None
    p = {k: float(v) for k, v in params.items()}
    vmax = float(max(model.max_velocity))
    amax = float(max(model.max_acceleration))
    if kind == FilterType.NONE:
        return ServoFilterSpec()
    if kind == FilterType.JOINT_LPF:
        return ServoFilterSpec(kind, cutoff=_in("lpf_cutoff_hz", p.get("lpf_cutoff_hz", 0.0),
                                                *CUTOFF_HZ, " Hz", open_low=False,
                                                clamp=clamp))
    if kind in (FilterType.JOINT_NLF, FilterType.CARTESIAN_NLF):
        rotation = kind == FilterType.CARTESIAN_NLF
        v_hi, a_hi = ((LIMIT_FACTOR * MAX_TOOL_ROTATION_SPEED,
                       LIMIT_FACTOR * MAX_TOOL_ROTATION_ACCEL)
                      if rotation else (LIMIT_FACTOR * vmax, LIMIT_FACTOR * amax))
        v = _in("nlf_max_vr", p.get("nlf_max_vr", 0.0), 0.0, v_hi, " rad/s", clamp=clamp)
        a = _in("nlf_max_ar", p.get("nlf_max_ar", 0.0), 0.0, a_hi, " rad/s²", clamp=clamp)
        j = _in("nlf_max_jr", p.get("nlf_max_jr", 0.0), 0.0, JERK_PER_ACCEL * a_hi, " rad/s³", clamp=clamp)
        if not rotation:
            return ServoFilterSpec(kind, velocity=v, accel=a, jerk=j)
        vp_hi, ap_hi = (LIMIT_FACTOR * model.max_tcp_speed * 1e3,
                        LIMIT_FACTOR * model.max_tcp_accel * 1e3)
        vp = _in("nlf_max_vp", p.get("nlf_max_vp", 0.0), 0.0, vp_hi, " mm/s", clamp=clamp)
        ap = _in("nlf_max_ap", p.get("nlf_max_ap", 0.0), 0.0, ap_hi, " mm/s²", clamp=clamp)
        jp = _in("nlf_max_jp", p.get("nlf_max_jp", 0.0), 0.0, JERK_PER_ACCEL * ap_hi, " mm/s³", clamp=clamp)
        return ServoFilterSpec(kind, velocity=v, accel=a, jerk=j, linear_velocity=vp / 1e3,
                               linear_accel=ap / 1e3, linear_jerk=jp / 1e3)
    buffer = _buffer(p.get("mmf_buffer", 0.0), clamp)
    if kind == FilterType.SPEED_FORESIGHT:
        return ServoFilterSpec(kind, buffer=buffer,
                               kp=_in("mmf_kp", p.get("mmf_kp", 0.0), 0.0, MAX_WEIGHT, "",
                                      clamp=clamp))
    kp, kv, ka = (_in(name, p.get(name, 0.0), 0.0, MAX_WEIGHT, "", open_low=False,
                      clamp=clamp)
                  for name in ("mmf_kp", "mmf_kv", "mmf_ka"))
    if kp + kv + ka <= 0.0:
        raise invalid("mmf_kp, mmf_kv and mmf_ka are all 0: at least one weight must be > 0")
    return ServoFilterSpec(kind, buffer=buffer, kp=kp, kv=kv, ka=ka)


def lag_of(spec: ServoFilterSpec) -> Optional[Tuple[str, float]]:
    """(what, s): the filter's lag behind a steady ramp where a closed form gives it (the mean
    filters' and the low-pass's), for the answer; None otherwise."""
    n = spec.buffer
    if spec.type == FilterType.JOINT_LPF:
        return "time constant", 1.0 / (2.0 * math.pi * spec.cutoff)
    if spec.type == FilterType.JOINT_MMF:
        w = spec.kp + spec.kv + spec.ka
        return "lag behind a ramp", (spec.kp + 2 * spec.kv + 3 * spec.ka) / w * \
            (n - 1) / 2 * SERVO_CYCLE
    if spec.type == FilterType.SPEED_FORESIGHT:
        return "lag behind a ramp", 0.0
    return None
