"""A velocity jog on a controller: the twist integrated into a ``servo_j`` stream, one absolute
joint target per 8 ms cycle, by the one law of :mod:`jaka_driver.motion.velocity_jog` (the
twin's too).

Why a servo stream and not ``jog``: the protocol's continuous jog moves one axis at a time
(``jog_mode`` 1 with one ``jnum``), so it cannot follow a 6-D twist, and a new jog command per
axis change would start and stop each axis on the controller's own ramps. ``servo_j`` takes a
whole joint target each cycle: the driver integrates the twist with its own kinematics (the
model's, which :mod:`.arm_identity` checks against the controller's at every connection), and
every target is checked before it goes out — joint limits and speeds with the braking and
singularity slowdowns of the velocity jog — as the twin's servo_p checks its own. A servo
stream is never scaled by the controller's rapid rate: the backend scales the twist itself.

One thread (``jaka-twist``) per jog, on the wall clock: it sends a target every cycle until the
jog is stopped and at rest, then leaves servo mode if it entered it.
"""
from __future__ import annotations

import logging
import threading
import time
from typing import Callable, Optional

import numpy as np

from ..common.constants import SERVO_CYCLE
from ..common.results import Code, Result
from ..host import realtime
from ..motion.velocity_jog import VelocityJog
from ..protocol import commands, errors

log = logging.getLogger(__name__)


class TwistStreamer:
    """Streams ``jog`` from the joints ``q0`` (rad) with ``send(request) -> reply``;
    ``leave_servo()`` at the end when the stream entered servo mode itself."""

    def __init__(self, jog: VelocityJog, q0: np.ndarray, send: Callable,
                 leave_servo: Optional[Callable[[], None]]):
        self.jog = jog
        self._q = np.asarray(q0, float).copy()
        self._send = send
        self._leave_servo = leave_servo
        self._done = threading.Event()
        self._halt = threading.Event()
        #: why the stream ended early (None: it ran until stopped)
        self.outcome: Optional[Result] = None
        self._thread = threading.Thread(target=self._run, name="jaka-twist", daemon=True)

    @property
    def running(self) -> bool:
        return not self._done.is_set()

    def start(self) -> None:
        self._thread.start()

    def command(self, twist: np.ndarray) -> None:
        self.jog.command(twist)

    def stop(self) -> None:
        """Ramp to rest, then end."""
        self.jog.stop()

    def halt(self, result: Result) -> None:
        """End at once (the link is lost, the driver shuts down): the arm holds the last
        target."""
        self.outcome = result
        self._halt.set()

    @realtime.runs_periodically
    def _run(self) -> None:
        try:
            due = time.monotonic()
            while not self._halt.is_set():
                q = self.jog.next(self._q)
                if self.jog.at_rest:
                    return
                try:
                    reply = self._send(commands.servo_j(q))
                except errors.JakaProtocolError as exc:
                    self.outcome = Result.failure(Code.COMMUNICATION_ERROR,
                                                  f"velocity jog stopped: {exc}")
                    return
                if not reply.ok:
                    self.outcome = Result.failure(
                        Code.MOTION_STOPPED, "velocity jog stopped: the controller refused "
                        f"servo_j: {reply.error_msg or reply.error_code}")
                    return
                self._q = q
                due += SERVO_CYCLE
                delay = due - time.monotonic()
                if delay > 0:
                    self._halt.wait(delay)
                else:
                    due = time.monotonic()          # late: do not burst to catch up
        except Exception as exc:  # noqa: BLE001 - the stream must end, not hang
            log.exception("velocity jog stream failed")
            self.outcome = Result.failure(Code.COMMUNICATION_ERROR, f"velocity jog failed: "
                                          f"{exc!r}")
        finally:
            if self.outcome is not None:
                log.warning("%s", self.outcome.message)
            if self._leave_servo is not None and not self._halt.is_set():
                self._leave_servo()
            self._done.set()
