"""Identifying the tool on the twin's force/torque sensor: its mass and centroid, from the
sensor read at rest in several orientations (JAKA's ``start_torq_sensor_payload_identify``).

**The estimate** (:func:`estimate_payload`) is linear least squares. At rest in a pose whose
sensor turned ``R`` (sensor → world) the sensor reads, in its frame, the tool's weight and that
weight's moment, plus a constant offset (whatever zeroing left, or the whole bias of an
unzeroed sensor): with ``g = Rᵀ (0, 0, −9.81)``,

    F = m·g + b_F,    M = c × (m·g) + b_M = −[g]× (m·c) + b_M,

linear in the ten unknowns (m, m·c, b_F, b_M). Three poses whose gravity directions in the
sensor frame differ (not along one line: the differences must span the plane at least) make
it determined; more average the noise. :func:`spread` says how well a set of poses does,
before anything moves.

**The motion** (:class:`IdentificationRun`, a motion source of the physics thread): from the
servo setpoint through each pose by a synchronised joint move, waiting :data:`SETTLE_S` at each
for the arm to come to rest, then averaging the sensor for :data:`AVERAGE_S`; at the end the
estimate finishes the completion. Units: kg, m, N, N·m, rad, s.
"""
from __future__ import annotations

from typing import Callable, Optional, Sequence

import numpy as np

from ..backend.completion import Completion
from ..backend.force import GRAVITY, IdentificationState, IdentificationStatus, SensorPayload
from ..common.results import Code, Result
from ..motion.trajectory import JointTrajectory
from .motions import Motion, TrajectoryRun

SETTLE_S = 0.3          # s at rest before measuring
AVERAGE_S = 0.2         # s of samples averaged per pose
#: the smallest :func:`spread` a set of poses may have: below it the centroid and the offset
#: cannot be told apart (poses about one joint axis alone give 1e-7; the tool turned 45° from
#: down about two axes and a third way, 0.23)
MIN_SPREAD = 0.05


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _rows(rotation: np.ndarray, gravity: np.ndarray = GRAVITY) -> np.ndarray:
    """The six rows of the regression at one pose: wrench = rows @ (m, m·c, b_F, b_M)
    (``gravity`` m/s² in the frame ``rotation`` turns the sensor into)."""
    g = rotation.T @ gravity
    rows = np.zeros((6, 10))
    rows[:3, 0] = g
    rows[:3, 4:7] = np.eye(3)
    rows[3:, 1:4] = -_skew(g)
    rows[3:, 7:10] = np.eye(3)
    return rows


def spread(rotations: Sequence[np.ndarray], gravity: np.ndarray = GRAVITY) -> float:
    """How well poses turning the sensor by ``rotations`` determine mass, centroid and offset:
    the smallest singular value of the regression over its largest, its columns scaled to
    one length (0: they cannot; the sensor down, then turned 90° about x and about y: 0.41)."""
    a = np.vstack([_rows(r, gravity) for r in rotations])
    norms = np.linalg.norm(a, axis=0)
    if np.any(norms < 1e-9):        # an unknown no pose sees at all
        return 0.0
    s = np.linalg.svd(a / norms, compute_uv=False)
    return float(s[-1] / s[0])


def estimate_payload(rotations: Sequence[np.ndarray], wrenches: Sequence[np.ndarray],
                     gravity: np.ndarray = GRAVITY) -> tuple[SensorPayload, np.ndarray, float]:
    """(payload, offset (6), rms residual N) from the sensor's ``wrenches`` (6, sensor frame)
    at rest in poses turning it ``rotations`` (sensor → base) under ``gravity`` (m/s², base
    frame)."""
    a = np.vstack([_rows(r, gravity) for r in rotations])
    b = np.concatenate([np.asarray(w, float) for w in wrenches])
    theta, *_ = np.linalg.lstsq(a, b, rcond=None)
    mass = float(theta[0])
    centroid = theta[1:4] / mass if abs(mass) > 1e-6 else np.zeros(3)
    residual = float(np.sqrt(np.mean((a @ theta - b) ** 2)))
    return SensorPayload(mass, centroid), theta[4:10], residual


class IdentificationRun(Motion):
    """Through ``segments`` (joint trajectories, each from the end of the one before; the
    first from where the arm stands) measuring at rest before the first and after each:
    ``measure()`` gives the sensor's (general reading, rotation) of this cycle, or None when
    the sensor is off (the run fails). ``completion`` finishes with the estimate (value: a
    SensorPayload) or a failure; ``report(status)`` is told every change of status."""

    busy_reason = "the sensor's payload identification moves the arm"

    def __init__(self, segments: Sequence[JointTrajectory], cycle: float, tolerance: float,
                 measure: Callable[[], Optional[tuple]], completion: Completion,
                 report: Callable[[IdentificationStatus], None]):
        self.completion = completion
        #: m/s², base frame: the twin's gravity when the run started (the mounting's)
        self.gravity = np.array(GRAVITY, float)
        self._segments = list(segments)
        self._cycle = cycle
        self._tolerance = tolerance
        self._measure = measure
        self._report = report
        self._settle = round(SETTLE_S / cycle)
        self._average = round(AVERAGE_S / cycle)
        self.planned = sum(s.duration for s in segments) + \
            (len(segments) + 1) * (self._settle + self._average) * cycle
        self._elapsed = 0.0
        self._run: Optional[TrajectoryRun] = None
        self._dwell = 0
        self._samples: list = []
        self._rotations: list = []
        self._wrenches: list = []
        self.moving = False
        self._status(f"measuring pose 1 of {len(self._segments) + 1}")

    def _status(self, message: str, state: IdentificationState = IdentificationState.RUNNING,
                result=None) -> None:
        progress = 1.0 if state != IdentificationState.RUNNING else \
            min(self._elapsed / self.planned, 0.99)
        self._report(IdentificationStatus(state, progress, message, result))

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        self._elapsed += self._cycle
        if self._run is not None:                       # moving to the next pose
            q = self._run.next(q_sp, qd_sp, q_meas, qd_meas)
            if self._run.active:
                return q
            self._run = None
            self.moving = False
            self._status(f"measuring pose {len(self._wrenches) + 1} of "
                         f"{len(self._segments) + 1}")
            return q
        self._dwell += 1
        if self._dwell > self._settle:
            sample = self._measure()
            if sample is None:
                return self._fail("the sensor was switched off during the identification",
                                  q_sp)
            self._samples.append(sample)
        if self._dwell >= self._settle + self._average:
            self._rotations.append(np.mean([r for _, r in self._samples], axis=0))
            self._wrenches.append(np.mean([w for w, _ in self._samples], axis=0))
            self._samples, self._dwell = [], 0
            if len(self._wrenches) > len(self._segments):
                return self._finish(q_sp)
            segment = self._segments[len(self._wrenches) - 1]
            self._run = TrajectoryRun(segment, self._cycle, self._tolerance,
                                      "identification", Completion())
            self.moving = True
            self._status(f"moving to pose {len(self._wrenches) + 1} of "
                         f"{len(self._segments) + 1}")
        return q_sp

    def _finish(self, q):
        payload, offset, residual = estimate_payload(self._rotations, self._wrenches,
                                                     self.gravity)
        self.active = self.moving = False
        if payload.mass < 0:
            return self._fail(f"the readings give a negative mass ({payload.mass:.3f} kg): "
                              "the sensor's own offset drifted or the arm was pushed", q)
        c = payload.centroid * 1000.0
        message = (f"payload identified from {len(self._wrenches)} poses: {payload.mass:.3f} "
                   f"kg at ({c[0]:.1f}, {c[1]:.1f}, {c[2]:.1f}) mm (residual "
                   f"{residual:.3f} N)")
        self._status(message, IdentificationState.DONE, payload)
        self.completion.finish(Result.success(message, payload))
        return q

    def _fail(self, why: str, q):
        self.active = self.moving = False
        self._status(why, IdentificationState.FAILED)
        self.completion.finish(Result.failure(Code.MOTION_STOPPED, why))
        return q

    def abort(self, result: Result) -> None:
        """Replaced before finishing (stop_move, a protective stop): it failed."""
        self._status(f"identification stopped: {result.message}", IdentificationState.FAILED)
        super().abort(result)
