"""Following a joint trajectory on a JAKA controller: absolute ``servo_j`` set-points streamed
from a thread on the controller's 8 ms cycle.

``step_num`` > 1 decimates: every ``step_num``-th sample is sent with ``stepNum = step_num``, and
the controller interpolates over ``step_num`` × 8 ms (docs/protocol.md, "Servo mode"). A late set-point is
sent as soon as possible and none is skipped: skipping would double the implied joint speed of
the next step, which the controller refuses above 180°/s.

The stream owns servo mode for its duration when it had to enter it, and leaves it before
telling the caller the outcome, so a caller that moves on at once finds the mode as it was.
"""
from __future__ import annotations

import logging
import math
import threading
import time
from typing import Callable, Iterator, Optional, Tuple

import numpy as np

from ..backend.completion import Completion
from ..common.constants import SERVO_CYCLE
from ..common.results import Code, Result
from ..host import realtime
from ..protocol import commands, errors
from .move_watch import MoveWatch, joints_at

log = logging.getLogger(__name__)

SETTLE_TIMEOUT = 2.0  # s after the last set-point for the arm to arrive within 1e-3 rad


def setpoints(trajectory, step_num: int, cycle: float = SERVO_CYCLE
              ) -> Iterator[Tuple[float, np.ndarray, int]]:
    """``(t, q, n)``: joints ``q`` (rad) to be reached at ``t`` s in ``n`` cycles; the last
    one is the trajectory's final point."""
    duration = float(trajectory.duration)
    period = step_num * cycle
    count = max(1, math.ceil(duration / period - 1e-9))
    t_prev = 0.0
    for k in range(1, count + 1):
        t = min(k * period, duration)
        n = max(1, round((t - t_prev) / cycle))
        q, _ = trajectory.sample(t)
        yield t, np.asarray(q, float), n
        t_prev = t


class TrajectoryStreamer:
    """Streams one trajectory; ``completion`` finishes once the arm is in position at the end
    (success), or with -12 (stopped, refused set-point, fault) or -1 (link lost).

    ``send(request)`` sends one request and returns its reply (raising the protocol errors);
    ``leave_servo()`` is called at the end when the stream entered servo mode itself.
    """

    def __init__(self, trajectory, send: Callable, leave_servo: Optional[Callable[[], None]],
                 step_num: int = 1):
        self.trajectory = trajectory
        self.duration = float(trajectory.duration)
        self._send = send
        self._leave_servo = leave_servo
        self._step_num = max(1, int(step_num))
        self._all_sent = False
        goal = joints_at(np.asarray(trajectory.sample(self.duration)[0], float))
        #: Fed with status packets by the backend; judges arrival only after the last set-point.
        self.watch = MoveWatch("trajectory", lambda st: self._all_sent and goal(st),
                               need_inpos=False)
        #: What the caller waits on: finished after servo mode is restored.
        self.completion = Completion()
        self._thread = threading.Thread(target=self._run, name="jaka-trajectory", daemon=True)

    @property
    def running(self) -> bool:
        return not self.completion.done

    def start(self) -> None:
        self._thread.start()

    def stop(self, result: Result) -> None:
        """Stop sending; the arm holds the last set-point. ``result`` is what the caller
        is told."""
        self.watch.abort(result)

    @realtime.runs_periodically
    def _run(self) -> None:
        try:
            self._stream()
            if not self.watch.completion.done:
                self.watch.arm()
                self._all_sent = True
                if self.watch.completion.wait(SETTLE_TIMEOUT) is None:
                    self.watch.abort(Result.failure(
                        Code.MOTION_STOPPED, f"trajectory: not within 1e-3 rad of the final "
                        f"point {SETTLE_TIMEOUT:g} s after the last set-point"))
        except Exception as exc:  # noqa: BLE001 - the caller must always get an answer
            log.exception("trajectory stream failed")
            self.watch.abort(Result.failure(Code.COMMUNICATION_ERROR,
                                            f"trajectory stream failed: {exc!r}"))
        finally:
            if self._leave_servo is not None:
                self._leave_servo()
            self.completion.finish(self.watch.completion.result)

    def _stream(self) -> None:
        t0 = time.monotonic()
        for t, q, n in setpoints(self.trajectory, self._step_num):
            if self.watch.completion.done:
                return
            delay = t0 + t - n * SERVO_CYCLE - time.monotonic()   # due when its interval starts
            if delay > 0:
                time.sleep(delay)
            try:
                reply = self._send(commands.servo_j(q, step_num=n))
            except errors.ConnectionLost as exc:
                self.watch.abort(Result.failure(Code.NOT_CONNECTED,
                                                f"trajectory stopped at t = {t:.3f} s: {exc}"))
                return
            except errors.JakaProtocolError as exc:
                self.watch.abort(Result.failure(Code.COMMUNICATION_ERROR,
                                                f"trajectory stopped at t = {t:.3f} s: {exc}"))
                return
            if not reply.ok:
                self.watch.abort(Result.failure(
                    Code.MOTION_STOPPED, f"trajectory stopped at t = {t:.3f} s: the controller "
                    f"refused servo_j: {reply.error_msg or reply.error_code}"))
                return
