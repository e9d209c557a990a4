"""What runs now on a controller, as this driver started it: one slot, as the twin's physics
loop has one motion source.

The slot holds one :class:`Run` — a move the controller accepted (:class:`MoveRun`, ended by
its :class:`~.move_watch.MoveWatch`), a trajectory streamed as ``servo_j``
(:class:`TrajectoryRun`), a continuous jog (:class:`JogRun`), a velocity jog streamed as
``servo_j`` (:class:`TwistRun`), force control that drives the arm (:class:`ForceControlRun`:
admittance, constant force, tool drive) or a payload identification
(:class:`IdentificationRun`) — and each answers the same three questions: is it busy, end it
now telling its waiter why (:meth:`Run.abort`), and what does a status packet tell it. A new run
takes the slot only if the one there is not busy, or is a jog (:func:`keeps_out`: the
controller ends a jog itself on a fault, and the driver's own watchdog decides when a jog is
over, so a jog's end is not always seen here). Servo mode, as last confirmed with ``is_in_servomove`` or left by the controller
on its own, lives here too: it is what the servo runs run in.

:attr:`RunningMotion.moving` adds what the status stream says (``inpos``), so that motion the
driver did not start (a pendant, a program) counts as well.
"""
from __future__ import annotations

import threading
from typing import Callable, Optional, Type, TypeVar

from ..backend.completion import Completion
from ..common.results import Code, CommandRefused, Result
from ..protocol.status_packet import StatusPacket
from .move_watch import MoveWatch
from .servo_stream import TrajectoryStreamer
from .status_view import StatusView
from .twist_stream import TwistStreamer

R = TypeVar("R", bound="Run")


class Run:
    """One motion this driver started on the controller."""

    label = "motion"

    @property
    def busy(self) -> bool:
        raise NotImplementedError

    def abort(self, result: Result) -> None:
        """End now (a stop, the link lost, shutdown): whoever waits is told ``result``."""
        raise NotImplementedError

    def on_status(self, status: StatusPacket, received: float) -> None:
        """A status packet received at ``received`` (``time.time()`` s)."""


class MoveRun(Run):
    """A ``joint_move`` / ``moveL`` the controller accepted, until its watch ends it."""

    def __init__(self, watch: MoveWatch):
        self.watch = watch
        self.label = watch.label

    @property
    def busy(self) -> bool:
        return not self.watch.completion.done

    def abort(self, result: Result) -> None:
        self.watch.abort(Result(result.code, f"{self.label}: {result.message}"))

    def on_status(self, status: StatusPacket, received: float) -> None:
        self.watch.on_status(status, received)


class _StreamRun(Run):
    """A run streamed as ``servo_j`` by ``streamer`` in its own thread, busy while that runs."""

    def __init__(self, streamer):
        self.streamer = streamer

    @property
    def busy(self) -> bool:
        return self.streamer.running


class TrajectoryRun(_StreamRun):
    """A trajectory streamed as ``servo_j``, until its stream has ended (servo mode restored
    when the stream entered it)."""

    label = "trajectory"
    streamer: TrajectoryStreamer

    def abort(self, result: Result) -> None:
        self.streamer.stop(Result(result.code, f"{self.streamer.watch.label}: {result.message}"))

    def on_status(self, status: StatusPacket, received: float) -> None:
        self.streamer.watch.on_status(status, received)


class JogRun(Run):
    """A continuous jog of ``axis`` = (wire coord_map, jnum), until it is stopped."""

    label = "jog"

    def __init__(self, coord_map: int, jnum: int):
        self.axis = (coord_map, jnum)
        self._ended = False

    @property
    def busy(self) -> bool:
        return not self._ended

    def abort(self, result: Result) -> None:
        self._ended = True          # nobody waits on a jog; the controller has stopped it


class TwistRun(_StreamRun):
    """A velocity jog streamed as ``servo_j``, until it is at rest (or halted)."""

    label = "velocity jog"
    streamer: TwistStreamer

    def abort(self, result: Result) -> None:
        self.streamer.halt(result)


def _halted(status: StatusPacket) -> Optional[str]:
    """Why the controller has stopped whatever drove the arm, from a packet (None: it has
    not)."""
    if status.emergency_stop:
        return "emergency stop"
    if status.protective_stop:
        return f"protective stop ({status.errmsg})" if status.errmsg else "protective stop"
    if not status.enabled:
        return "the robot was disabled"
    return None


class ForceControlRun(Run):
    """Force control that drives the arm — ``mode`` a :class:`~jaka_driver.backend.force.
    ForceMode` value — from its confirmed start until it is ended: disabled, or halted by the
    controller (a protective stop, e.g. the sensor's soft limit, an e-stop, disable: a packet
    shows it). ``abort`` (stop_move, shutdown) ends it and calls ``on_abort`` to switch the
    controller's force control off too."""

    def __init__(self, mode: str, on_abort: Callable[[], None]):
        self.mode = mode
        self.label = mode.replace("_", " ")
        self._on_abort = on_abort
        self._ended = False

    @property
    def busy(self) -> bool:
        return not self._ended

    def end(self) -> None:
        """Ended by its own request (disable), or never started (the start was refused)."""
        self._ended = True

    def abort(self, result: Result) -> None:
        if not self._ended:
            self._ended = True
            self._on_abort()

    def on_status(self, status: StatusPacket, received: float) -> None:
        if not self._ended and _halted(status) is not None:
            self._ended = True


class IdentificationRun(Run):
    """A payload identification the controller runs (``start_torq_sensor_payload_identify``),
    until its ``completion`` is finished: by the poller reading the controller's status and
    result (:mod:`.force`), a halt a packet shows, or an abort."""

    label = "payload identification"

    def __init__(self, completion: Completion):
        self.completion = completion

    @property
    def busy(self) -> bool:
        return not self.completion.done

    def abort(self, result: Result) -> None:
        self.completion.finish(Result(result.code, f"{self.label}: {result.message}"))

    def on_status(self, status: StatusPacket, received: float) -> None:
        why = _halted(status)
        if why is not None and not self.completion.done:
            self.completion.finish(Result.failure(Code.MOTION_STOPPED,
                                                  f"{self.label} stopped: {why}"))


#: Why a busy run keeps the slot from the new one (None: the new one takes it)
Refusal = Callable[[Run], Optional[str]]


class RunningMotion:
    """The one slot of what runs now on the controller, and servo mode (see the module);
    ``view`` is the status stream's latest packet."""

    def __init__(self, view: StatusView):
        self._view = view
        self._lock = threading.Lock()
        #: the run in the slot (busy or not: the last one started)
        self.current: Optional[Run] = None
        #: servo mode as last confirmed (``is_in_servomove``), or left by the controller on its
        #: own (a fault in a packet, a refused target, the link lost)
        self.servo_mode = False

    def running(self, kind: Type[R]) -> Optional[R]:
        """The run in the slot if it is a busy ``kind``, else None."""
        run = self.current
        return run if isinstance(run, kind) and run.busy else None

    def check(self, refusal: Refusal) -> None:
        """Refuse (-10) with ``refusal(busy run)`` when the busy run in the slot gives a
        reason; before anything is sent for a new run."""
        run = self.current
        if run is not None and run.busy:
            why = refusal(run)
            if why is not None:
                raise CommandRefused(Code.BUSY, why)

    def take(self, run: Run, refusal: Refusal) -> None:
        """Put ``run`` in the slot, unless :meth:`check` refuses it: checked and put at
        once."""
        with self._lock:
            self.check(refusal)
            self.current = run

    def end_jog(self) -> Optional[JogRun]:
        """The busy jog in the slot, now counted as ended (its stop is the caller's to send),
        or None."""
        with self._lock:
            jog = self.running(JogRun)
            if jog is not None:
                jog.abort(Result.success("jog ended"))
            return jog

    def abort(self, result: Result) -> None:
        """End whatever runs now; its waiter is told ``result`` (labelled with the run)."""
        run = self.current
        if run is not None:
            run.abort(result)

    def on_status(self, status: StatusPacket, received: float) -> None:
        run = self.current
        if run is not None:
            run.on_status(status, received)

    @property
    def moving(self) -> bool:
        """A run of this driver is busy, or the latest status packet shows the arm not in
        position."""
        run = self.current
        latest = self._view.latest
        return (run is not None and run.busy) or (latest is not None and not latest.inpos)


def keeps_out(what: str) -> Refusal:
    """The slot's rule for a new ``what``: a busy move, trajectory or velocity jog keeps it out
    (the refusal names the run); a jog keeps nothing out."""
    def refusal(run: Run) -> Optional[str]:
        if isinstance(run, JogRun):
            return None
        if isinstance(run, TrajectoryRun):
            return f"{what} refused: a trajectory runs"
        if isinstance(run, ForceControlRun):
            return (f"{what} refused: force control holds the arm ({run.label}; "
                    "disable_force_control first)")
        return f"{what} refused: {run.label} is still running (stop_move first)"
    return refusal
