"""support.threads.join_all, the join the suite's threaded tests rely on: a thread still alive
after the timeout fails the test, by name (Thread.join alone returns quietly, so a test whose
threads deadlock would pass); threads that end pass, within one deadline for all of them."""
import threading
import time

import pytest

from support.threads import join_all, run_all


def test_a_thread_still_alive_after_the_timeout_fails_naming_it():
    release = threading.Event()
    stuck = threading.Thread(target=release.wait, name="stuck worker", daemon=True)
    quick = threading.Thread(target=lambda: None, name="quick worker")
    try:
        with pytest.raises(AssertionError, match=r"1 of 2 threads still alive.*stuck worker"):
            run_all([quick, stuck], 0.05)
    finally:
        release.set()
        stuck.join(1.0)


def test_threads_that_end_pass_within_one_deadline():
    threads = [threading.Thread(target=time.sleep, args=(0.05,)) for _ in range(4)]
    run_all(threads, 5.0)
    assert not any(t.is_alive() for t in threads)


def test_the_deadline_is_shared_not_per_thread():
    """Ten stuck threads, 0.2 s: a join of 0.2 s each would take 2 s; the shared deadline
    returns after 0.2 s (the bound halfway leaves a busy machine 0.8 s of scheduling)."""
    release = threading.Event()
    stuck = [threading.Thread(target=release.wait, daemon=True) for _ in range(10)]
    for t in stuck:
        t.start()
    t0 = time.monotonic()
    try:
        with pytest.raises(AssertionError):
            join_all(stuck, 0.2)
        assert time.monotonic() - t0 < 1.0
    finally:
        release.set()
        join_all(stuck, 1.0)
