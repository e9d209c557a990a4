"""Payload identification on a controller, as JAKA's SDK runs it: the start went out
(``start_torq_sensor_payload_identify``, :mod:`.force`); then ``get_torq_sensor_identify_staus``
every :data:`IDENTIFY_POLL` s until it reads done (0) or failed (2), then
``get_torq_sensor_payload_identify_result`` — and the plan the driver waits against.

Units: joints rad, mass kg, centroid m (mm on the wire), s.
"""
from __future__ import annotations

import time
from typing import Callable, Optional

import numpy as np

from ..backend.completion import Completion
from ..backend.force import IdentificationState, IdentificationStatus, SensorPayload
from ..common.models import RobotModel
from ..common.results import Code, CommandRefused, Result
from ..motion.profiles import joint_move_profile
from ..protocol import torque_sensor as wire
from .commander import Commander

#: s between two get_torq_sensor_identify_staus while an identification runs
IDENTIFY_POLL = 0.1
#: s after the start during which "done" (0) is taken for the previous run's, until the
#: controller has said "running" (1) once
IDENTIFY_START_GRACE = 1.0
#: The controller's own pace of an identification is not on record: the plan (the door's
#: deadline, 1.5 × plan + 2 s) assumes a joint move at this share of the joints' limits and
#: IDENTIFY_MEASURE_S of measuring
IDENTIFY_PACE = 0.1
IDENTIFY_MEASURE_S = 2.0
#: s planned when the arm's joints are not known yet
UNKNOWN_PLAN = 30.0
WHAT = "payload identification"


def identification_plan(model: RobotModel, q0: Optional[np.ndarray], q_end: np.ndarray) -> float:
    """s an identification from joints ``q0`` to ``q_end`` (rad) is planned to take."""
    if q0 is None or not np.all(np.isfinite(q0)):
        return UNKNOWN_PLAN
    plan = joint_move_profile(q0, q_end, model.max_velocity * IDENTIFY_PACE,
                              model.max_acceleration * IDENTIFY_PACE)
    return plan.duration + IDENTIFY_MEASURE_S


def follow_identification(send: Commander, completion: Completion, planned: float,
                          report: Callable[[IdentificationStatus], None]) -> None:
    """Poll the controller's identification status through ``send`` until it is done or
    failed, then read the result into ``completion`` (its value the :class:`SensorPayload`);
    ``report`` every status on the way. Ends early when ``completion`` is finished elsewhere
    (a stop, a halt in a packet). Runs in its own thread (``jaka-identify``)."""
    t0 = time.monotonic()
    seen_running = False
    while not completion.wait(IDENTIFY_POLL):
        elapsed = time.monotonic() - t0
        try:
            state = send.read(wire.get_torq_sensor_identify_staus(), wire.reply_identify_status)
            if state == IdentificationState.RUNNING:
                seen_running = True
                report(IdentificationStatus(IdentificationState.RUNNING, min(0.99, elapsed / planned),
                                            f"{WHAT} running ({elapsed:.1f} s)"))
                continue
            if state == IdentificationState.DONE and not seen_running and elapsed < IDENTIFY_START_GRACE:
                continue            # the previous run's "done": not begun yet
            if state != IdentificationState.DONE:
                raise CommandRefused(Code.CONTROLLER_REJECTED, f"{WHAT} failed: the "
                                     f"controller reports identify_status {state}")
            mass, centroid_mm = send.read(wire.get_torq_sensor_payload_identify_result(),
                                          wire.reply_identify_result)
        except CommandRefused as refusal:
            report(IdentificationStatus(IdentificationState.FAILED, 0.0, refusal.message))
            completion.finish(refusal.result())
            return
        payload = SensorPayload(float(mass), np.asarray(centroid_mm, float) / 1000.0)
        message = (f"{WHAT} done in {elapsed:.1f} s: {payload.mass:.3f} kg at "
                   f"({centroid_mm[0]:.1f}, {centroid_mm[1]:.1f}, {centroid_mm[2]:.1f}) mm")
        report(IdentificationStatus(IdentificationState.DONE, 1.0, message, payload))
        completion.finish(Result.success(message, payload))
        return
    result = completion.result
    if result is not None and not result.ok:
        report(IdentificationStatus(IdentificationState.FAILED, 0.0, result.message))
