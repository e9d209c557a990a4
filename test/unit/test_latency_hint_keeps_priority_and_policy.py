"""The latency hint asks only for a shorter time slice: the threads started after it inherit
the slice, the process keeps its nice value and SCHED_OTHER, and a process started at
real-time priority is left there. Each case runs in a child process of its own, so this
test process's scheduling is untouched."""
import os
import subprocess
import sys

import pytest

from jaka_driver.host.latency_hint import SLICE_S
from support.scheduling import kernel_has_custom_slices

CHILD = """
import os, threading
from jaka_driver.host import latency_hint
message = latency_hint.request_short_slice()
seen = []
t = threading.Thread(target=lambda: seen.append(latency_hint.current_slice_s()))
t.start(); t.join()
print(message)
print(seen[0])
print(os.getpriority(os.PRIO_PROCESS, 0), os.sched_getscheduler(0))
"""


def _child(prefix=(), preexec=None) -> tuple[str, str, list[int]]:
    out = subprocess.run([*prefix, sys.executable, "-c", CHILD], capture_output=True,
                         text=True, timeout=30, preexec_fn=preexec, check=True)
    message, thread_slice, prio_policy = out.stdout.strip().splitlines()
    return message, thread_slice, [int(x) for x in prio_policy.split()]


def test_a_thread_started_after_the_request_has_the_short_slice():
    message, thread_slice, (nice, policy) = _child()
    if kernel_has_custom_slices():
        assert message == "time slice 0.2 ms for this process's threads (latency-sensitive)"
        assert float(thread_slice) == pytest.approx(SLICE_S, abs=1e-9)
    else:
        assert "no custom slices" in message
    assert (nice, policy) == (0, os.SCHED_OTHER)


def test_the_nice_value_the_process_was_started_with_is_kept():
    message, _, (nice, policy) = _child(preexec=lambda: os.nice(7))
    assert nice == 7 and policy == os.SCHED_OTHER, message


def test_a_process_at_real_time_priority_stays_there():
    try:
        subprocess.run(["chrt", "-f", "1", "true"], check=True, capture_output=True)
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("real-time priority needs CAP_SYS_NICE or an rtprio limit here")
    message, _, (_, policy) = _child(prefix=("chrt", "-f", "1"))
    assert message == "no short time slice: the process runs at real-time priority already"
    assert policy == os.SCHED_FIFO
