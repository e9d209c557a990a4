"""The outcome of a motion that a caller may wait on (blocking services, the trajectory action,
the emulator's ``inpos``)."""
from __future__ import annotations

import threading
from typing import Optional

from ..common.results import Result


class Completion:
    """Set once, by whoever runs the motion (the physics thread, a status-stream watcher)."""

    def __init__(self):
        self._event = threading.Event()
        self.result: Optional[Result] = None

    def finish(self, result: Result) -> None:
        if not self._event.is_set():
            self.result = result
            self._event.set()

    def wait(self, timeout: float, clock=None) -> Optional[Result]:
        """The result, or None after ``timeout`` s (of ``clock``'s time, default the wall
        clock: jaka_driver.backend.clock)."""
        done = self._event.wait(timeout) if clock is None else clock.wait(self._event, timeout)
        return self.result if done else None

    @property
    def done(self) -> bool:
        return self._event.is_set()
