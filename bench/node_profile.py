"""Where the driver node's CPU goes: py-spy samples of the running node (zu5 twin) while a
subscriber takes the three state topics, idle and while servo_j streams at 125 Hz.

``python -m bench.node_profile [--seconds 15] [--node PATH] [--top 12]`` starts a private
rosmaster and the node, attaches ``py-spy record`` (``--nonblocking``: the node is not paused
to be sampled) for each window, and prints per window the node's CPU (% of one core, from
``/proc``) and the functions with the most samples: *own* (the function was on top of the
stack, running Python or a C call it made) and *total* (anywhere on the stack), as % of
the samples in which a thread held the interpreter lock (``--gil``: C work that releases
the lock, as MuJoCo's ``mj_step`` does, and waiting threads are left out; the share of
samples taken at all is the share of time the lock was held). ``--node`` runs another checkout's
``scripts/jaka_driver_node``, to profile the code before a change side by side with after.
Not part of ``make bench``: py-spy needs ptrace rights on the node.
"""
from __future__ import annotations

import argparse
import collections
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import ExitStack
from pathlib import Path

import numpy as np

from . import ros_session
from .proc_meter import CpuWindow

RATE_HZ = 125.0


def py_spy() -> str:
    """The py-spy executable: the venv's (requirements.txt), else one on PATH."""
    here = Path(sys.executable).parent / "py-spy"
    found = str(here) if here.exists() else shutil.which("py-spy")
    if not found:
        raise RuntimeError("py-spy not found: pip install the pin of requirements.txt")
    return found


def record(pid: int, seconds: float) -> tuple[list[tuple[list[str], int]], float]:
    """Collapsed stacks ``([frames root→leaf], count)`` of ``pid`` over ``seconds`` and the
    process's CPU over the same window (% of one core)."""
    out = Path(tempfile.mkdtemp(prefix="node_profile_")) / "stacks.txt"
    with CpuWindow(pid) as cpu:
        subprocess.run([py_spy(), "record", "--pid", str(pid), "--duration", str(int(seconds)),
                        "--rate", "250", "--nonblocking", "--gil", "--format", "raw", "--output",
                        str(out)], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
    stacks = []
    for line in out.read_text().splitlines():
        frames, _, count = line.rpartition(" ")
        stacks.append((frames.split(";"), int(count)))
    return stacks, cpu.as_dict()["cpu_percent"]


def _name(frame: str) -> str:
    """``function (file.py:line)`` → ``function (file.py)``."""
    fn, _, where = frame.partition(" (")
    return f"{fn} ({where.split(':')[0].rsplit('/', 1)[-1].rstrip(')')})" if where else fn


def hot(stacks, top: int) -> tuple[int, list[tuple[str, float, float]]]:
    """(samples, [(function, own %, total %)]) with thread-name frames left out."""
    own, total = collections.Counter(), collections.Counter()
    n = 0
    for frames, count in stacks:
        names = [_name(f) for f in frames if not f.startswith("thread ")
                 and not f.startswith("process ")]
        if not names:
            continue
        n += count
        own[names[-1]] += count
        for name in set(names):
            total[name] += count
    ranked = sorted(own, key=lambda k: -own[k])[:top]
    return n, [(k, 100.0 * own[k] / n, 100.0 * total[k] / n) for k in ranked]


def stream_servo(driver, calls, stop: threading.Event) -> None:
    """servo_j at 125 Hz, a slow sine on joint 6, until ``stop``."""
    import rospy
    from jaka_msgs.srv import ServoMove, ServoMoveEnable
    from sensor_msgs.msg import JointState
    q0 = np.array(rospy.wait_for_message(driver.name("joint_position"), JointState,
                                         timeout=5).position)
    calls("servo_move_enable", ServoMoveEnable, enable=True)
    proxy = rospy.ServiceProxy(driver.name("servo_j"), ServoMove, persistent=True)
    start, k = time.monotonic(), 0
    try:
        while not stop.is_set():
            q = q0.copy()
            q[5] += 0.2 * np.sin(2 * np.pi * 0.5 * k / RATE_HZ)
            proxy(pose=q.tolist())
            k += 1
            time.sleep(max(0.0, start + k / RATE_HZ - time.monotonic()))
    finally:
        proxy.close()
        calls("servo_move_enable", ServoMoveEnable, enable=False)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.node_profile",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=15.0)
    parser.add_argument("--node", help="another checkout's scripts/jaka_driver_node")
    parser.add_argument("--top", type=int, default=12)
    args = parser.parse_args(argv)
    from support import ros_harness
    if args.node:
        ros_harness.NODE = Path(args.node)
    from .state_topics import TOPICS
    with ExitStack() as stack:
        ros_session.start_ros(stack)
        driver = ros_session.start_driver(stack, "node_profile", backend="sim", model="zu5")
        calls = ros_session.services(stack, driver)
        for name, msg_type in TOPICS:
            ros_session.recorder(stack, driver.name(name), msg_type)
        time.sleep(1.0)
        for window in ("idle", "servo streaming"):
            stop = threading.Event()
            streamer = None
            if window == "servo streaming":
                streamer = threading.Thread(target=stream_servo, args=(driver, calls, stop))
                streamer.start()
                time.sleep(0.5)
            stacks, cpu = record(driver.proc.pid, args.seconds)
            stop.set()
            if streamer is not None:
                streamer.join()
            n, rows = hot(stacks, args.top)
            print(f"\n## {window}: node CPU {cpu:.1f} % of one core; interpreter lock held in {n} "
                  f"samples ({100.0 * n / (250 * args.seconds):.1f} % of the time)")
            print(f"{'own %':>6} {'total %':>7}  function")
            for name, own_pct, total_pct in rows:
                print(f"{own_pct:6.1f} {total_pct:7.1f}  {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
