"""Force control on the twin: admittance, constant force and tool drive as one motion source
(:class:`ForceControlRun`), run by the physics thread at the twin's 8 ms cycle.

Each cycle the measured wrench (the sensor's ``real`` or ``actual``, jaka_driver.backend.force)
is expressed in the force-control frame — the active tool's axes, or the base's, moments about
the TCP — and low-pass filtered (:data:`CONTROL_FILTER_HZ`); each enabled axis then asks for a
speed by the admittance law of jaka_driver.backend.force::

    v_i = COMPLIANT_SPEED_i · (w_i + constant_i − rebound_i · x_i) / ft_user_i

(``x_i`` the displacement since force control started; free axes ignore a wrench inside
:data:`DEAD_BAND`, so noise and what zeroing left do not make the arm creep; every speed is
capped at COMPLIANT_SPEED). That twist drives a velocity jog (jaka_driver.motion.velocity_jog):
the same ramp, joint speed caps, braking before joint limits and singularity slowdown as
``~twist_command``, so force control never leaves the limits of a jog.

**Why the filter, and the gains it allows.** The arm is position-driven: the joint drives
track each setpoint within a cycle, and their velocity feed-forward makes a contact force
answer a setpoint's speed at once, so against a surface the loop force → speed → force has its
largest gain at the cycle's own rate (62.5 Hz), where the samples alternate and the tool
bounces. Measured on a Zu 5 pressing MuJoCo's default contact (about 30 kN/m with the arm's
own compliance, probe tip 1–3 mm above the table): unfiltered, constant force chatters at any
``ft_user`` up to 200 N; through a 10 Hz filter it settles for ``ft_user`` ≥ 60 N; through 3 Hz
for ``ft_user`` ≥ 20 N (2 N lower it chatters), reaching 10 ± 0.5 N 0.1–0.3 s after touching at
``ft_user`` 20–80 N and holding it within ±0.02 N; softer contacts (solref time constant
0.05 s, damping ratio 2–4) settle the same way. 3 Hz keeps the usable range of ``ft_user``
down to where JAKA's examples set it, and its 53 ms lag is below what a hand on the tool
notices (tool drive). Below about 20 N per 0.1 m/s the arm chatters on a stiff surface, as a
real one does with too much gain: the filter is not a guard against that.

Units: N, N·m, m, rad, s; twists (vx vy vz m/s, wx wy wz rad/s) in the force-control frame.
"""
from __future__ import annotations

import math
from typing import Callable, Optional, Sequence

import numpy as np

from ..backend.force import COMPLIANT_SPEED, ForceFrame, rebound_to_si
from ..common.transforms import matrix_to_rotvec
from ..motion.velocity_jog import VelocityJog
from .motions import Motion

#: Hz, the low-pass of the wrench force control acts on (the module says why)
CONTROL_FILTER_HZ = 3.0
#: N and N·m: a free axis (no constant force) ignores a wrench this small
DEAD_BAND = np.array([1.0, 1.0, 1.0, 0.05, 0.05, 0.05])


class AxisLaws:
    """The six axes' admittance (see the module): ``gain`` (m/s per N, rad/s per N·m; 0 for a
    disabled axis), ``constant`` (N, N·m), ``rebound`` (N/m, N·m/rad)."""

    def __init__(self, gain: Sequence[float], constant: Sequence[float],
                 rebound: Sequence[float]):
        self.gain = np.asarray(gain, float)
        self.constant = np.asarray(constant, float)
        self.rebound = np.asarray(rebound, float)
        self.free = self.constant == 0.0
        self.speed = np.asarray(COMPLIANT_SPEED, float)

    @classmethod
    def of(cls, axes, stiffness_of, constant_of) -> "AxisLaws":
        """From six axis settings: ``stiffness_of(axis)`` the wrench that moves the axis at the
        compliant speed (``ft_user``, ``rigidity``), ``constant_of(axis)`` its constant force
        (0: none)."""
        gain = [COMPLIANT_SPEED[i] / stiffness_of(a) if a.enabled else 0.0
                for i, a in enumerate(axes)]
        return cls(gain, [constant_of(a) if a.enabled else 0.0 for a in axes],
                   [rebound_to_si(i, a.rebound) if a.enabled else 0.0
                    for i, a in enumerate(axes)])

    def twist(self, wrench: np.ndarray, displacement: np.ndarray) -> np.ndarray:
        """The speeds (6) asked for by ``wrench`` (6, force-control frame) at
        ``displacement`` (6, m and rad since the start)."""
        w = np.where(self.free, np.sign(wrench) * np.maximum(np.abs(wrench) - DEAD_BAND, 0.0),
                     wrench)
        v = self.gain * (w + self.constant - self.rebound * displacement)
        return np.clip(v, -self.speed, self.speed)


def wrench_at_tcp(wrench: np.ndarray, tool: np.ndarray, flange: np.ndarray,
                  frame: int) -> np.ndarray:
    """``wrench`` (sensor frame = flange, moments about its origin) as force control sees it:
    moments about the TCP of ``tool`` (flange → tool, 4x4), along the tool's axes
    (:attr:`ForceFrame.TOOL`) or the base's (``flange``: base → flange, 4x4)."""
    force, moment = wrench[:3], wrench[3:] - np.cross(tool[:3, 3], wrench[:3])
    rotation = tool[:3, :3].T if frame == ForceFrame.TOOL else flange[:3, :3]
    return np.concatenate([rotation @ force, rotation @ moment])


def displacement(start: np.ndarray, now: np.ndarray, frame: int) -> np.ndarray:
    """How far the TCP moved from ``start`` to ``now`` (4x4, m), along and about the axes of
    ``frame`` (the tool's as it stands now, or the base's)."""
    if frame == ForceFrame.TOOL:
        return np.concatenate([now[:3, :3].T @ (now[:3, 3] - start[:3, 3]),
                               matrix_to_rotvec(start[:3, :3].T @ now[:3, :3])])
    return np.concatenate([now[:3, 3] - start[:3, 3],
                           matrix_to_rotvec(now[:3, :3] @ start[:3, :3].T)])


class ForceControlRun(Motion):
    """Admittance, constant force or tool drive (``mode``, a ForceMode value): each cycle the
    wrench from ``wrench()`` (sensor frame, None while the sensor is off: the arm brakes to
    rest) drives ``jog`` by ``laws`` in ``frame``. ``tcp(q)``, ``flange(q)``: the active tool's
    and the flange's pose in the base (4x4) at joints ``q``; ``tool`` flange → tool (4x4).
    Runs until :meth:`stop`, then ramps to rest and ends."""

    busy_reason = "force control holds the arm (disable_force_control first)"

    def __init__(self, mode: str, laws: AxisLaws, frame: int, jog: VelocityJog,
                 wrench: Callable[[], Optional[np.ndarray]], tcp: Callable, flange: Callable,
                 tool: np.ndarray, q0: np.ndarray, cycle: float):
        self.mode = mode
        self.laws = laws
        self.frame = frame
        self.jog = jog
        self._wrench = wrench
        self._tcp, self._flange, self._tool = tcp, flange, tool
        self._start = tcp(q0)
        self._alpha = 1.0 - math.exp(-2.0 * math.pi * CONTROL_FILTER_HZ * cycle)
        self._filtered: Optional[np.ndarray] = None
        self._stopping = False
        self.moving = False

    def stop(self) -> None:
        """Ramp to rest and end (disable, stop_move)."""
        self._stopping = True
        self.jog.stop()

    @property
    def stopping(self) -> bool:
        """Told to stop: force control is off, the arm ramps to rest."""
        return self._stopping

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        if not self._stopping:
            self.jog.command(self._twist(q_sp))
        q = self.jog.next(q_sp)
        self.moving = bool(self.jog.ramp.velocity.any())
        if self._stopping and self.jog.at_rest:
            self.active = self.moving = False
        return q

    def _twist(self, q: np.ndarray) -> np.ndarray:
        measured = self._wrench()
        if measured is None:            # the sensor went off: nothing to comply with
            self._filtered = None
            return np.zeros(6)
        w = wrench_at_tcp(measured, self._tool, self._flange(q), self.frame)
        if self._filtered is None:
            self._filtered = w
        else:
            self._filtered = self._filtered + self._alpha * (w - self._filtered)
        return self.laws.twist(self._filtered, displacement(self._start, self._tcp(q),
                                                            self.frame))
