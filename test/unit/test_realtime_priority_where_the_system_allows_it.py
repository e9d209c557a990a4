"""Real-time priority (jaka_driver.host.realtime) goes to the cycle's threads only: one running
when it is granted and one that starts later run at SCHED_FIFO, every other thread keeps the
default policy; without the privilege nothing changes and the message says what would allow
it; 0 leaves the default policy; a priority outside 0–99 is refused. Each case runs in a child
process of its own, so this test process's scheduling is untouched."""
import json
import os
import resource
import subprocess
import sys

import pytest

from jaka_driver.host import realtime
from support.scheduling import may_use_fifo

CHILD = """
import json, os, sys, threading
from jaka_driver.host import realtime
NAMES = {os.SCHED_OTHER: "SCHED_OTHER", os.SCHED_FIFO: "SCHED_FIFO"}
policy_name = lambda: NAMES.get(os.sched_getscheduler(0), "another policy")
seen = {}
ready, done = threading.Event(), threading.Event()

@realtime.runs_periodically
def cycle(name, before=None):
    if before is not None:
        before.set()
    done.wait(10)
    seen[name] = policy_name()

def other():
    done.wait(10)
    seen["other"] = policy_name()

threads = [threading.Thread(target=cycle, args=("before", ready)),
           threading.Thread(target=other)]
for t in threads:
    t.start()
ready.wait(10)
message = realtime.request_realtime(int(sys.argv[1]))
late = threading.Thread(target=cycle, args=("after",))
late.start()
threads.append(late)
done.set()
for t in threads:
    t.join()
# a cycle thread that ended is no longer registered: a later grant does not reach its id
print(json.dumps({"message": message, "main": policy_name(), **seen,
                  "registered": len(realtime._periodic_threads)}))
"""
NOBODY = 65534


def _child(priority: int, preexec=None) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, str(priority)], capture_output=True,
                         text=True, timeout=60, preexec_fn=preexec, env=os.environ.copy())
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def _as_nobody():
    """A preexec that drops to user nobody, rtprio limit 0: a user without the privilege."""
    def drop():
        resource.setrlimit(resource.RLIMIT_RTPRIO, (0, 0))
        os.setgroups([])
        os.setgid(NOBODY)
        os.setuid(NOBODY)
    return drop


def test_the_periodic_threads_run_and_start_at_the_priority_and_no_other_thread_does():
    if not may_use_fifo():
        pytest.skip("this machine gives the tests neither CAP_SYS_NICE nor an rtprio limit")
    got = _child(10)
    assert got["message"] == ("real-time priority SCHED_FIFO 10 for the periodic threads (1 now, "
                              "and those that start later); the others at the default policy")
    assert (got["before"], got["after"]) == ("SCHED_FIFO", "SCHED_FIFO"), got
    assert (got["main"], got["other"]) == ("SCHED_OTHER", "SCHED_OTHER"), got
    assert got["registered"] == 0


def test_without_the_privilege_nothing_changes_and_the_log_says_what_would_allow_it():
    if os.geteuid() != 0:
        pytest.skip("dropping to another user needs root")
    got = _child(10, _as_nobody())
    assert got["message"] == ("no real-time priority: SCHED_FIFO 10 needs root, CAP_SYS_NICE "
                              "or an rtprio limit ≥ 10 (ulimit -r is 0); the threads keep the "
                              "default policy"), got
    assert {got[k] for k in ("main", "before", "after", "other")} == {"SCHED_OTHER"}, got


def test_priority_0_leaves_the_default_policy():
    got = _child(0)
    assert got["message"].startswith("real-time priority off"), got
    assert {got[k] for k in ("main", "before", "after", "other")} == {"SCHED_OTHER"}, got


@pytest.mark.parametrize("priority", [-1, 100, 1000])
def test_a_priority_outside_fifo_s_range_is_refused_and_changes_nothing(priority):
    assert realtime.priority_error(priority) == (
        f"realtime_priority {priority}; expected 0 (off) or 1–99 (SCHED_FIFO)")
    got = _child(priority)
    assert got["message"] == f"no real-time priority: {realtime.priority_error(priority)}"
    assert {got[k] for k in ("main", "before", "after", "other")} == {"SCHED_OTHER"}, got
