"""JAKA's mean filters, on each joint: the multi-order mean (``filter_type`` 3, MMF) and the
speed foresight (5, "velocity look-ahead: an extended version of the multi-order filter with a
look-ahead algorithm"). JAKA publishes their parameters (``max_buf``, ``kp``, ``kv``, ``ka``)
but not their algorithms; these are the driver's, with the parameters meaning what JAKA's SDK
header and guide say of them.

**Multi-order mean** (``buffer`` N, weights ``kp``, ``kv``, ``ka`` ≥ 0): three moving means of
the last N targets in a chain — the first of the targets, the second of the first's outputs,
the third of the second's. A step through one mean becomes a ramp over N cycles (the position
is averaged; the velocity jumps), through two an S of continuous velocity, through three of
continuous acceleration. The output is their weighted average, (kp·m₁ + kv·m₂ + ka·m₃) /
(kp + kv + ka): ``kp`` weighs the position mean, ``kv`` the velocity-smooth one, ``ka`` the
acceleration-smooth one; only the ratios matter (JAKA's examples, 0.2/0.4/0.2 and 2/4/2, are
the same filter). It never overshoots; behind a steady ramp it lags (kp + 2kv + 3ka) /
(kp + kv + ka) × (N − 1)/2 cycles; a larger buffer is smoother and lags more.

**Speed foresight** (``buffer`` N, ``kp`` in (0, 1]): the second-order mean m₂ of the targets
(lag N − 1 cycles), its velocity v̂ (per cycle), and the target predicted from them,
m₂ + v̂·(N − 1) cycles — the look-ahead that takes the mean's lag back on a steady ramp —
kept within the lowest and highest of the last N targets. Each cycle the output moves by v̂
plus the share ``kp`` of its distance to the prediction, towards the prediction and never past
it: once settled it does not lag a steady ramp; it does not overshoot a step; a smaller ``kp`` is
smoother and slower to close a gap (JAKA: "reducing kp smoother, greater loss of position
accuracy; increasing it faster and more accurate, with jitter when the data are noisy").
"""
from __future__ import annotations

import numpy as np


class _MovingMean:
    """The mean of the last ``n`` inputs (per axis), started full of one value."""

    def __init__(self, n: int):
        self.n = n
        self._buf = None
        self._k = 0
        self._sum = None

    def reset(self, value) -> None:
        value = np.asarray(value, float)
        self._buf = np.tile(value, (self.n, 1))
        self._sum = value * self.n
        self._k = 0

    def next(self, value) -> np.ndarray:
        value = np.asarray(value, float)
        self._sum = self._sum + value - self._buf[self._k]
        self._buf[self._k] = value
        self._k = (self._k + 1) % self.n
        return self._sum / self.n

    def span(self) -> tuple[np.ndarray, np.ndarray]:
        """(lowest, highest) of the inputs it holds, per axis."""
        return self._buf.min(axis=0), self._buf.max(axis=0)


class JointMultiOrderMean:
    def __init__(self, buffer: int, kp: float, kv: float, ka: float):
        self._means = [_MovingMean(buffer) for _ in range(3)]
        total = kp + kv + ka
        self._weights = (kp / total, kv / total, ka / total)

    def reset(self, q, pose=None) -> None:
        for mean in self._means:
            mean.reset(q)

    def next(self, q_target, pose=None) -> np.ndarray:
        m1 = self._means[0].next(q_target)
        m2 = self._means[1].next(m1)
        m3 = self._means[2].next(m2)
        wp, wv, wa = self._weights
        return wp * m1 + wv * m2 + wa * m3


class SpeedForesight:
    def __init__(self, buffer: int, kp: float):
        self._means = [_MovingMean(buffer) for _ in range(2)]
        self._ahead = buffer - 1            # cycles: the two means' lag on a ramp
        self.kp = kp
        self._last = self._out = None

    def reset(self, q, pose=None) -> None:
        for mean in self._means:
            mean.reset(q)
        self._last = np.array(q, float)
        self._out = np.array(q, float)

    def next(self, q_target, pose=None) -> np.ndarray:
        first = self._means[0]
        m2 = self._means[1].next(first.next(q_target))
        step = m2 - self._last                       # v̂ per cycle
        self._last = m2
        # look ahead by the means' lag, never beyond what the targets themselves have been
        predicted = np.clip(m2 + step * self._ahead, *first.span())
        gap = predicted - self._out
        move = step + self.kp * gap
        # towards the prediction, at most all the way: it never runs past it
        self._out = self._out + np.clip(move, np.minimum(gap, 0.0), np.maximum(gap, 0.0))
        return self._out.copy()
