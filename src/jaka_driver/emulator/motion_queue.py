"""A controller's motion queue on the twin: a move is acknowledged at once and runs after the
ones before it (docs/protocol.md, "Motion queue"); ``inpos`` only once the queue is done.

:class:`MotionQueue` keeps the queued moves and starts each, in a thread of its own
(``emulator-motion-queue``), when the one before it has ended. A move that cannot start when
its turn comes, or one that is stopped, clears the queue, as ``stop_program`` does. What a move
is and whether it may be queued are the controller's rules (:mod:`.twin_controller`); this
module only keeps the order and the time.

Thread-safe: a move is started under the controller's lock (``lock``: a controller executes one
command at a time); the counters are read without it.
"""
from __future__ import annotations

import collections
import logging
import threading
from typing import Callable, Deque, Optional, Tuple

from ..backend import Completion
from ..common.results import Code, Result
from .replies import Rejected

log = logging.getLogger(__name__)

QUEUE_SIZE = 64                   # moves the queue holds; one more is refused (queue_full)

#: A queued move: (label, start) where start() returns the twin's Result of a started move.
QueuedMove = Tuple[str, Callable[[], Result]]


class MotionQueue:
    """The queued moves of a controller whose commands are serialised by ``lock`` (see the
    module); its thread runs from construction to :meth:`close`."""

    def __init__(self, lock: threading.RLock):
        self.lock = lock
        self._pending: Optional[Completion] = None    # the running move, until it ends
        # A move taken from the queue and being started (planned): it counts as moving, so
        # a client never sees the queue done between two queued moves.
        self._starting = False
        #: the label of the move started last ("joint_move", "moveL", "jog", ...)
        self.running_label = ""
        self._queue: Deque[QueuedMove] = collections.deque()
        self._queue_changed = threading.Condition(threading.Lock())
        #: moves started so far (the status packet's ``motion_line``)
        self.motion_line = 0
        self._quit = threading.Event()
        self._worker = threading.Thread(target=self._run, daemon=True,
                                        name="emulator-motion-queue")
        self._worker.start()

    def close(self) -> None:
        self._quit.set()
        with self._queue_changed:
            self._queue_changed.notify_all()
        self._worker.join(2.0)

    def enqueue(self, label: str, start: Callable[[], Result]) -> None:
        """Queue a move; it is acknowledged now and starts when the moves before it have
        ended. Refused when the queue is full."""
        with self.lock:
            if len(self._queue) >= QUEUE_SIZE:
                raise Rejected(f"{label}: the motion queue is full ({QUEUE_SIZE} moves)")
            self._queue.append((label, start))
        with self._queue_changed:
            self._queue_changed.notify_all()

    def clear(self) -> None:
        """Forget the moves not started yet (the running one is the caller's to stop)."""
        with self.lock:
            self._queue.clear()

    @property
    def active(self) -> int:
        """Moves not done: the running one (or the one being started) and those queued."""
        pending = self._pending
        running = self._starting or (pending is not None and not pending.done)
        return len(self._queue) + int(running)

    @property
    def queued(self) -> int:
        """Moves waiting behind the running one. A move acknowledged while the queue was idle
        is the running one from its acknowledgement on, whether or not this queue's thread has
        taken it yet: a client asking at once sees the same counts as a moment later."""
        return max(self.active - 1, 0)

    @property
    def moving(self) -> bool:
        """A queued move waits, is being started, or runs."""
        return self.active > 0

    def _run(self) -> None:
        while not self._quit.is_set():
            with self._queue_changed:
                while not self._queue and not self._quit.is_set():
                    self._queue_changed.wait(0.5)
                if self._quit.is_set():
                    return
            with self.lock:
                if not self._queue:
                    continue
                self._starting = True           # before the queue looks empty (lock-free readers)
                label, start = self._queue.popleft()
                try:
                    started = start()
                except Exception as exc:  # noqa: BLE001 - the queue must survive a bad move
                    log.exception("emulator: queued %s failed", label)
                    started = Result.failure(Code.INVALID_PARAMETER, f"{label}: {exc!r}")
                self.motion_line += 1
                if not started.ok:
                    log.warning("emulator: queued %s refused when its turn came: %s; the queue "
                                "is cleared", label, started.message)
                    self._queue.clear()
                    self._starting = False
                    continue
                self._pending, self.running_label = started.value[0], label
                self._starting = False
            outcome = started.value[0]
            while outcome.wait(0.1) is None and not self._quit.is_set():
                pass
            if outcome.result is not None and not outcome.result.ok:
                with self.lock:
                    self._queue.clear()   # a stopped move ends the queue, as stop_program does
