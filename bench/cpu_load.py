""""Both cores loaded": busy-looping subprocesses that the benchmark starts and stops.

Each worker is a plain ``python -c 'while True: pass'`` in its own process group at the
default priority (nice 0, like the node), so it competes with the node for the CPU exactly as
an unrelated busy program on the same machine would.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time


class BusyLoad:
    """``workers`` busy processes (default: one per CPU) while the ``with`` block runs."""

    def __init__(self, workers: int | None = None):
        self.workers = workers or os.cpu_count() or 2
        self.procs: list[subprocess.Popen] = []

    def __enter__(self) -> "BusyLoad":
        try:
            for _ in range(self.workers):
                self.procs.append(subprocess.Popen(
                    [sys.executable, "-c", "while True: pass"], stdin=subprocess.DEVNULL,
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                    start_new_session=True))
            time.sleep(0.5)   # let the scheduler see them as CPU hogs
        except BaseException:
            self.stop()
            raise
        return self

    def stop(self) -> None:
        """SIGKILL every worker's process group and reap it. Idempotent."""
        for proc in self.procs:
            if proc.poll() is None:
                try:
                    os.killpg(proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            proc.wait()
        self.procs.clear()

    def __exit__(self, *exc) -> None:
        self.stop()
