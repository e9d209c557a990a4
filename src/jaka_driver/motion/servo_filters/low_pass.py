"""``filter_type`` 1, JAKA's "first-order low-pass filter in joint space": per joint, each 8 ms
cycle the output moves the share α of the way to the target, α = 1 − exp(−2π·f_c·T) — the
exact discretisation of a first-order lag of cut-off ``f_c`` Hz (time constant τ = 1/(2π·f_c))
at the cycle T. It never overshoots; a step is 63 % there after τ, a sine of frequency f lags
by atan(f/f_c)/(2π·f) and is scaled by 1/√(1 + (f/f_c)²). JAKA's guide: the lower the cut-off,
the smoother and the less accurate; from about 40 Hz on no difference is seen on an arm.
"""
from __future__ import annotations

import math

import numpy as np


class JointLowPass:
    def __init__(self, cutoff_hz: float, cycle: float):
        self.alpha = 1.0 - math.exp(-2.0 * math.pi * cutoff_hz * cycle)
        self._y = None

    def reset(self, q, pose=None) -> None:
        self._y = np.array(q, float)

    def next(self, q_target, pose=None) -> np.ndarray:
        self._y = self._y + self.alpha * (np.asarray(q_target, float) - self._y)
        return self._y.copy()
