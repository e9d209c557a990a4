"""Start-up time: ``roslaunch jaka_driver jaka_driver.launch`` → first ``joint_position``.

A subscriber to ``/jaka_driver/joint_position`` is in place before roslaunch starts (against
the benchmark's running rosmaster, so no master start is counted); the time is from the
``Popen`` of roslaunch to the receipt of the first message. ``RUNS`` launches, each stopped
(SIGINT to its process group, then SIGKILL; the nodes it started are checked for and stopped
too) before the next; the median is judged. For the note, the time a fresh interpreter takes
to import what the node imports is measured once.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from sensor_msgs.msg import JointState

from . import ros_session
from .report import Row, at_most, judged

RUNS = 3
TARGET_S = 3.0
TIMEOUT_S = 30.0


def _children(pid: int) -> list[int]:
    """Direct child processes of ``pid`` (roslaunch starts each node in its own session, so
    stopping roslaunch's process group does not reach them)."""
    out = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as f:
                out += [int(c) for c in f.read().split()]
    except OSError:
        pass
    return out


def _stop_launch(proc: subprocess.Popen, nodes: list[int]) -> None:
    """Stop roslaunch (it stops its nodes), then make sure no node it started outlives it."""
    ros_session.stop_process(proc)
    for pid in nodes:
        for sig, wait in ((signal.SIGINT, 5.0), (signal.SIGKILL, 2.0)):
            if not os.path.exists(f"/proc/{pid}"):
                break
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                break
            ros_session.wait_until(lambda: not os.path.exists(f"/proc/{pid}"), wait)


def launch_once(log_dir: Path, k: int) -> tuple[float, float, float]:
    """Seconds from roslaunch to its first node process existing, to the first
    joint_position message, and to the services being advertised; NaN for what did not
    happen within ``TIMEOUT_S``. The launch is stopped only once the node is ready: a node
    interrupted while still starting up may not stop on SIGINT."""
    import rospy
    rec = ros_session.Recorder("/jaka_driver/joint_position", JointState)
    log = open(log_dir / f"bench_startup_{k}.log", "wb")
    proc = None
    nodes: list[int] = []
    spawned = ready = float("nan")
    try:
        time.sleep(0.3)
        t0 = time.time()
        proc = subprocess.Popen(["roslaunch", "jaka_driver", "jaka_driver.launch"],
                                stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                start_new_session=True, env=os.environ.copy())
        while not rec.samples and proc.poll() is None and time.time() - t0 < TIMEOUT_S:
            if not nodes:
                nodes = _children(proc.pid)
                if nodes:
                    spawned = time.time() - t0
            time.sleep(0.002)
        first = rec.samples[0][0] - t0 if rec.samples else float("nan")
        try:
            rospy.wait_for_service("/jaka_driver/clear_err", timeout=TIMEOUT_S)
            ready = time.time() - t0
        except rospy.ROSException:
            pass
        return spawned, first, ready
    finally:
        if proc is not None:
            _stop_launch(proc, sorted(set(nodes) | set(_children(proc.pid))))
        rec.close()
        log.close()


def import_seconds() -> float:
    """Wall time (s) of a fresh interpreter importing what the node imports."""
    t0 = time.monotonic()
    subprocess.run([sys.executable, "-c", "import rospy, jaka_driver.ros.node, "
                    "jaka_driver.sim.backend"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, env=os.environ.copy())
    return time.monotonic() - t0


def run(runs: int = RUNS) -> dict:
    log_dir = Path(os.environ.get("ROS_LOG_DIR", "/tmp"))
    log_dir.mkdir(parents=True, exist_ok=True)
    imports = import_seconds()
    spawned, times, ready = [], [], []
    for k in range(runs):
        node_s, first_s, ready_s = launch_once(log_dir, k)
        spawned.append(node_s)
        times.append(first_s)
        ready.append(ready_s)
        time.sleep(0.5)       # the old node's registrations are gone before the next launch
    return {"startup_s": times, "node_spawned_s": spawned, "services_ready_s": ready,
            "imports_s": imports, "log_dir": str(log_dir)}


def rows(r: dict) -> list[Row]:
    t = np.array(r["startup_s"])
    ok = np.isfinite(t)
    median = float(np.median(t[ok])) if ok.any() else float("inf")
    passed = bool(ok.all()) and median <= TARGET_S
    ready = np.array(r.get("services_ready_s", []), float)
    ready_text = (f"; services ready at {np.nanmedian(ready):.2f} s"
                  if ready.size and np.isfinite(ready).any() else "")
    value = (f"median {median:.2f} s, worst {np.max(t[ok]):.2f} s "
             f"({ok.sum()} of {t.size} launches{ready_text})" if ok.any() else "no message")
    spawned = np.array(r.get("node_spawned_s", []), float)
    imports = r.get("imports_s")
    split = ""
    if spawned.size and np.isfinite(spawned).any() and imports:
        roslaunch_s = float(np.nanmedian(spawned))
        split = (f"Median split: roslaunch takes {roslaunch_s:.2f} s before it starts the "
                 f"node process (its own interpreter and imports, parsing, parameters); the "
                 f"node then takes {median - roslaunch_s:.2f} s to its first message, of "
                 f"which {imports:.2f} s is a fresh interpreter importing rospy, MuJoCo and "
                 "Pinocchio (the node starts through /usr/bin/env python3 and re-executes "
                 "itself in the venv) and the rest building the twin, Pinocchio model and "
                 "ROS registrations. ")
    note = ""
    if not passed:
        note = (f"{split}Lazy imports (MuJoCo and Pinocchio only once the backend is built, "
                "rospy message modules on first use), a precompiled MJB model, and starting "
                "the node with the venv interpreter directly would cut it.")
    elif ok.any() and np.max(t[ok]) > TARGET_S:
        note = (f"the median passes, one launch took {np.max(t[ok]):.2f} s. {split}"
                "Slow launches come with a busy machine (see the load line above).")
    return [Row("Start-up", "roslaunch → first joint_position (median of launches)", value,
                f"≤ {TARGET_S:g} s", judged(passed), note, data={"startup_s": t},
                bounds=at_most(median if ok.any() else None, TARGET_S, "s", "median"))]
