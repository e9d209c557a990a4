"""The outcome of a motion that a caller may wait on (blocking services, the trajectory action,
the emulator's ``inpos``)."""
from __future__ import annotations

import threading
from typing import Optional

from .results import Result


class Completion:
    """Set once, by whoever runs the motion (the physics thread, a status-stream watcher)."""

    def __init__(self):
        self._event = threading.Event()
        self.result: Optional[Result] = None

    def finish(self, result: Result) -> None:
        if not self._event.is_set():
            self.result = result
            self._event.set()

    def wait(self, timeout: float) -> Optional[Result]:
        return self.result if self._event.wait(timeout) else None

    @property
    def done(self) -> bool:
        return self._event.is_set()
