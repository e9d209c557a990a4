"""Threads a test starts and must see end: ``Thread.join(timeout)`` returns quietly when the
timeout passes, so a test that only joins passes while its threads hang (a deadlock, a call that
never returns). :func:`join_all` fails the test instead, naming the threads still alive."""
from __future__ import annotations

import threading
import time
from typing import Iterable


def join_all(threads: Iterable[threading.Thread], timeout: float) -> None:
    """Join every thread within ``timeout`` s (one deadline for all of them); an
    AssertionError names those still alive after it."""
    threads = list(threads)
    deadline = time.monotonic() + timeout
    for thread in threads:
        thread.join(max(0.0, deadline - time.monotonic()))
    alive = [t.name for t in threads if t.is_alive()]
    assert not alive, f"{len(alive)} of {len(threads)} threads still alive after " \
                      f"{timeout:g} s: {', '.join(alive)}"


def run_all(threads: Iterable[threading.Thread], timeout: float) -> None:
    """Start every thread, then :func:`join_all` them."""
    threads = list(threads)
    for thread in threads:
        thread.start()
    join_all(threads, timeout)
