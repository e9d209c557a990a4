"""Where the driver node's time goes, window by window: CPU per thread, wake-ups per sample,
the garbage collector's pauses and the functions that hold the interpreter lock, while each
of the bench rows it explains runs.

``python -m bench.node_profile [--seconds 10] [--windows idle,servo,...] [--node PATH]
[--against PATH] [--rounds 1] [--top 12]`` starts a private rosmaster and the node (zu5 twin,
or the controller backend on the emulator), a subscriber on the three state topics, and for
each window attaches ``py-spy record`` (``--nonblocking``: the node is not paused to be
sampled; ``--threads``: each sample names its thread) and prints:

* the node's CPU (% of one core, ``/proc``), and per thread its CPU and its wake-ups per 8 ms
  cycle — voluntary context switches (it slept on a lock, a timer, a socket) and involuntary
  ones (the scheduler took its core) — (:mod:`bench.thread_meter`); on the controller
  windows the emulator's too;
* the garbage collector: collections and pause time per generation (``gc.callbacks`` in the
  node, :mod:`bench.probe_site`);
* the functions with the most samples: *own* (the function was on top of the stack, running
  Python or a C call it made) and *total* (anywhere on the stack), as % of the samples in
  which a thread held the interpreter lock (``--gil``: C work that releases the lock, as
  MuJoCo's ``mj_step`` does, and waiting threads are left out; the share of samples taken
  at all is the share of time the lock was held), and the same split by thread.

Windows (``--windows``, comma-separated): ``idle`` (the twin, nothing asked), ``servo`` (servo_j
at 125 Hz through the service), ``rtt`` (back-to-back servo_j calls with their round trips),
``twist`` (a teleop's ``~twist_command`` at 125 Hz),
``twist-starts`` (bench.stream_inputs' bursts from rest: per start, the first twist →
first moving sample and the floor of that start), ``ctl-idle``, ``ctl-servo``, ``ctl-rtt``
(the controller backend through the emulator: nothing asked, the servo_j stream, back-to-back
servo_j calls with their round trips).

``--spy-emulator`` samples the emulator instead of the node on the controller windows (its
share of a round trip). ``--node`` runs another checkout's ``scripts/jaka_driver_node`` (and that checkout's emulator);
``--against`` profiles a second checkout in the same run, each window on one node and then on
the other (``--rounds`` times, the order swapped each round), so that before and after a
change share the machine's minute. Not part of ``make bench``: py-spy needs ptrace rights on
the node.
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import ExitStack, contextmanager
from pathlib import Path

import numpy as np

from . import ros_session
from .proc_meter import CpuWindow, MachineWindow
from .thread_meter import ThreadWindow

RATE_HZ = 125.0
SAMPLE_RATE = 250           # py-spy samples per second
ROOT = Path(__file__).resolve().parents[1]
PROBE_SITE = Path(__file__).resolve().parent / "probe_site"
SIM_WINDOWS = ("idle", "servo", "rtt", "twist", "twist-starts", "loaded")
CONTROLLER_WINDOWS = ("ctl-idle", "ctl-servo", "ctl-rtt", "ctl-loaded")


def py_spy() -> str:
    """The py-spy executable: the venv's (requirements.txt), else one on PATH."""
    here = Path(sys.executable).parent / "py-spy"
    found = str(here) if here.exists() else shutil.which("py-spy")
    if not found:
        raise RuntimeError("py-spy not found: pip install the pin of requirements.txt")
    return found


class GcProbe:
    """Reads the totals :mod:`bench.probe_site` writes in the node (once a second)."""

    def __init__(self, path: Path):
        self.path = path

    def read(self) -> dict | None:
        try:
            return json.loads(self.path.read_text())
        except (OSError, ValueError):
            return None

    @staticmethod
    def between(a: dict | None, b: dict | None) -> dict | None:
        if not a or not b or a.get("pid") != b.get("pid") or b["time"] <= a["time"]:
            return None
        span = b["time"] - a["time"]
        return {"seconds": span,
                "per_s": [(n1 - n0) / span for n0, n1 in zip(a["collections"],
                                                              b["collections"])],
                "pause_ms_per_s": [1e3 * (p1 - p0) / span for p0, p1 in zip(a["pause_s"],
                                                                           b["pause_s"])],
                "max_ms": [1e3 * m for m in b["max_s"]],
                "over_1ms": b["over_1ms"] - a["over_1ms"]}


def sched_delays(data: Path, pids: set[int]) -> dict[int, list[float]]:
    """tid → scheduling delays (ms: from being woken, or preempted, to running) of the
    threads of ``pids`` in a ``perf sched record`` file (``perf sched timehist``)."""
    text = subprocess.run(["perf", "sched", "timehist", "-i", str(data)], capture_output=True,
                          text=True).stdout
    out: dict[int, list[float]] = collections.defaultdict(list)
    for line in text.splitlines()[3:]:
        parts = line.split()
        if len(parts) < 6 or "[" not in parts[2]:
            continue
        ids = parts[2].rsplit("[", 1)[1].rstrip("]").split("/")
        try:
            tid = int(ids[0])
            pid = int(ids[1]) if len(ids) > 1 else tid
            delay = float(parts[4])
        except ValueError:
            continue
        if pid in pids:
            out[tid].append(delay)
    return out


@contextmanager
def profiled(pid: int, gc_probe: GcProbe | None, extra_pids: dict | None = None,
             sched: bool = False):
    """py-spy, per-thread counters and the GC totals of ``pid`` over the ``with`` block;
    yields a dict filled at its end (``stacks``, ``cpu``, ``threads``, ``gc``, ``seconds``,
    ``machine``, ``extra``: the threads of each of ``extra_pids``, name → pid; with
    ``sched``, ``sched``: tid → scheduling delays, ms, of the node's, the extra processes'
    and this process's threads, from ``perf sched``)."""
    out: dict = {}
    perf_data = Path(tempfile.mkdtemp(prefix="node_profile_sched_")) / "perf.data"
    perf = subprocess.Popen(["perf", "sched", "record", "-a", "-o", str(perf_data)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) \
        if sched else None
    stacks_file = Path(tempfile.mkdtemp(prefix="node_profile_")) / "stacks.txt"
    spy = subprocess.Popen([py_spy(), "record", "--pid", str(pid), "--rate", str(SAMPLE_RATE),
                            "--nonblocking", "--gil", "--threads", "--format", "raw",
                            "--output", str(stacks_file)], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    time.sleep(0.5)     # py-spy attached
    gc0 = gc_probe.read() if gc_probe else None
    extra = {name: ThreadWindow(p).start() for name, p in (extra_pids or {}).items()}
    threads = ThreadWindow(pid).start()
    with MachineWindow() as machine, CpuWindow(pid) as cpu:
        t0 = time.monotonic()
        try:
            yield out
        finally:
            out["seconds"] = time.monotonic() - t0
    threads.stop()
    for w in extra.values():
        w.stop()
    if perf is not None:
        perf.send_signal(signal.SIGINT)
        perf.wait(30)
        out["sched"] = sched_delays(perf_data, {pid, os.getpid(), *(extra_pids or {}).values()})
        shutil.rmtree(perf_data.parent, ignore_errors=True)
    time.sleep(1.05 if gc_probe else 0.0)        # the probe's next write covers the window
    out["gc"] = GcProbe.between(gc0, gc_probe.read()) if gc_probe else None
    spy.send_signal(signal.SIGINT)
    try:
        spy.wait(10)
    except subprocess.TimeoutExpired:
        spy.kill()
        spy.wait()
    stacks = []
    if stacks_file.exists():
        for line in stacks_file.read_text().splitlines():
            frames, _, count = line.rpartition(" ")
            if frames:
                stacks.append((frames.split(";"), int(count)))
    out.update(stacks=stacks, cpu=cpu.percent, threads=threads, machine=machine.percent,
               extra=extra)


def _name(frame: str) -> str:
    """``function (file.py:line)`` → ``function (file.py)``."""
    fn, _, where = frame.partition(" (")
    return f"{fn} ({where.split(':')[0].rsplit('/', 1)[-1].rstrip(')')})" if where else fn


def _thread_of(frames: list[str]) -> tuple[int | None, str]:
    """(tid, name) from py-spy's ``thread (tid): name`` frame, else (None, "")."""
    head = frames[0] if frames else ""
    if not head.startswith("thread ("):
        return None, ""
    tid, _, name = head[len("thread ("):].partition("): ")
    try:
        return int(tid, 0), name
    except ValueError:
        return None, name


def hot(stacks, top: int) -> tuple[int, list[tuple[str, float, float]]]:
    """(samples, [(function, own %, total %)]) with thread and process frames left out."""
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
    return n, [(k, 100.0 * own[k] / max(n, 1), 100.0 * total[k] / max(n, 1)) for k in ranked]


def by_thread(stacks) -> tuple[dict[int, str], collections.Counter]:
    """(tid → thread name, thread name → interpreter-lock samples)."""
    names, held = {}, collections.Counter()
    for frames, count in stacks:
        tid, name = _thread_of(frames)
        if tid is not None:
            names[tid] = name
        held[name or "?"] += count
    return names, held


def stream_servo(driver, calls, stop: threading.Event, rtt: list | None = None,
                 paced: bool = True) -> None:
    """servo_j until ``stop``: at 125 Hz a slow sine on joint 6 (``paced``), or back to back
    holding the arm still; each call's round trip (s) is appended to ``rtt`` if given."""
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
            if paced:
                q[5] += 0.2 * np.sin(2 * np.pi * 0.5 * k / RATE_HZ)
            t0 = time.perf_counter()
            proxy(pose=q.tolist())
            if rtt is not None:
                rtt.append(time.perf_counter() - t0)
            k += 1
            if paced:
                time.sleep(max(0.0, start + k / RATE_HZ - time.monotonic()))
    finally:
        proxy.close()
        calls("servo_move_enable", ServoMoveEnable, enable=False)


def stream_twists(driver, stop: threading.Event) -> None:
    """A teleop's ``~twist_command`` at 125 Hz (bench.stream_inputs' sine) until ``stop``."""
    from . import stream_inputs
    from jaka_driver.common.constants import SERVO_CYCLE
    pub = stream_inputs._publisher(driver, "twist_command", stream_inputs.TwistStamped)
    start, i = time.monotonic(), 0
    while not stop.is_set():
        pub.publish(stream_inputs.base_twist(stream_inputs.TWIST_SPEED * np.cos(
            2 * np.pi * 0.5 * i * SERVO_CYCLE)))
        i += 1
        time.sleep(max(0.0, start + i * SERVO_CYCLE - time.monotonic()))
    time.sleep(stream_inputs.REST_WAIT_S)


def twist_starts(driver, trials: int) -> str:
    """bench.stream_inputs' bursts from rest; one line per start: latency, floor, driver."""
    from . import stream_inputs
    from jaka_driver.common.constants import SERVO_CYCLE
    from sensor_msgs.msg import JointState
    joints = ros_session.Recorder(driver.name("joint_position"), JointState)
    try:
        ros_session.wait_until(joints.latest, 5.0)
        got = stream_inputs.twist_trials(driver, joints, trials)
    finally:
        joints.close()
    latency = 1e3 * (got["moved"] - got["sent"])
    floor = 1e3 * (got["arrival_end"] - got["sent"] + SERVO_CYCLE)
    part = latency - floor
    listed = " ".join(f"{d:.1f}" for d in part)
    return (f"first twist → moving sample p50 / p99 / max {np.nanpercentile(latency, 50):.1f} / "
            f"{np.nanpercentile(latency, 99):.1f} / {np.nanmax(latency):.1f} ms; floor p99 "
            f"{np.nanpercentile(floor, 99):.1f} ms; driver's part p50 / p99 "
            f"{np.nanpercentile(part, 50):.1f} / {np.nanpercentile(part, 99):.1f} ms; per start "
            f"(ms, in order): {listed}")


def loaded_topics(driver, seconds: float) -> str:
    """Both cores loaded (bench.cpu_load): joint_position's inter-arrival for ``seconds``, then
    the bare timer loop's (bench.scheduler_floor) under the same load."""
    from sensor_msgs.msg import JointState
    from .cpu_load import BusyLoad
    from .scheduler_floor import timer_loop
    with BusyLoad():
        rec = ros_session.Recorder(driver.name("joint_position"), JointState)
        try:
            ros_session.wait_until(rec.latest, 5.0)
            t0 = time.time()
            time.sleep(seconds)
            recv = np.array([t for t, _ in rec.since(t0)])
        finally:
            rec.close()
        loop = timer_loop(min(seconds, 10.0))
    topic = 1e3 * np.diff(recv)
    bare = 1e3 * np.diff(loop["woke"])
    return (f"joint_position inter-arrival p50 / p99 / max {np.percentile(topic, 50):.2f} / "
            f"{np.percentile(topic, 99):.2f} / {topic.max():.2f} ms; the bare loop's "
            f"{np.percentile(bare, 50):.2f} / {np.percentile(bare, 99):.2f} / {bare.max():.2f} "
            "ms (right after, same load)")


def run_window(window: str, driver, calls, seconds: float) -> str:
    """Run ``window``'s workload for ``seconds`` (the starts: their own length); a line of
    what it measured, or ""."""
    stop = threading.Event()
    if window == "twist-starts":
        return twist_starts(driver, max(4, int(seconds)))
    if window in ("loaded", "ctl-loaded"):
        return loaded_topics(driver, seconds)
    rtt: list = []
    work = {"servo": lambda: stream_servo(driver, calls, stop),
            "ctl-servo": lambda: stream_servo(driver, calls, stop),
            "ctl-rtt": lambda: stream_servo(driver, calls, stop, rtt, paced=False),
            "rtt": lambda: stream_servo(driver, calls, stop, rtt, paced=False),
            "twist": lambda: stream_twists(driver, stop)}.get(window)
    worker = threading.Thread(target=work) if work else None
    if worker:
        worker.start()
    time.sleep(seconds)
    stop.set()
    if worker:
        worker.join()
    if rtt:
        a = 1e3 * np.array(rtt[10:])
        return (f"servo_j round trip p50 / p99 / max {np.percentile(a, 50):.3f} / "
                f"{np.percentile(a, 99):.3f} / {a.max():.3f} ms ({a.size} calls)")
    return ""


def _delays(values) -> str:
    if not values:
        return "—"
    a = np.asarray(values)
    return f"{np.percentile(a, 50):.2f}/{np.percentile(a, 99):.2f}/{a.max():.2f}"


def _own_tids() -> set[int]:
    return {int(t) for t in os.listdir(f"/proc/{os.getpid()}/task")}


def report(label: str, window: str, got: dict, measured: str, top: int) -> None:
    n, rows = hot(got["stacks"], top)
    names, held = by_thread(got["stacks"])
    threads = got["threads"]
    seconds = got["seconds"]
    print(f"\n## {window} — {label}: node CPU {got['cpu']:.1f} % of one core (machine "
          f"{got['machine']:.0f} %), interpreter lock held {100.0 * n / (SAMPLE_RATE * seconds):.1f}"
          f" % of the time; {threads.total_per_cycle():.2f} context switches per 8 ms cycle")
    if measured:
        print(f"   {measured}")
    delays = got.get("sched") or {}
    print(f"{'CPU %':>6} {'vol/cyc':>7} {'inv/cyc':>7} {'GIL %':>6}"
          + (f" {'sched delay p50/p99/max ms':>27}" if delays else "") + "  thread")
    for name, cpu, vol, inv in threads.rows(names):
        short = name.rsplit(" (", 1)[0]
        tid = int(name.rsplit("(", 1)[1].rstrip(")"))
        print(f"{cpu:6.1f} {vol:7.2f} {inv:7.2f} {100.0 * held.get(short, 0) / max(n, 1):6.1f}"
              + (f" {_delays(delays.get(tid)):>27}" if delays else "") + f"  {name}")
    if delays:
        mine = [d for tid, ds in delays.items() if tid in _own_tids() for d in ds]
        print(f"   this process (the subscriber) sched delay p50/p99/max {_delays(mine)} ms")
    for what, w in got["extra"].items():
        total = sum(t["cpu_percent"] for t in w.threads.values())
        print(f"   {what}: CPU {total:.1f} %, {w.total_per_cycle():.2f} context switches per "
              "cycle; busiest: " + ", ".join(
                  f"{r[0]} {r[1]:.1f} % {r[2]:.2f}+{r[3]:.2f}/cyc" for r in w.rows({}, 4)))
    g = got["gc"]
    if g:
        print(f"   GC: collections/s gen0 {g['per_s'][0]:.1f}, gen1 {g['per_s'][1]:.2f}, gen2 "
              f"{g['per_s'][2]:.3f}; pause ms/s {sum(g['pause_ms_per_s']):.3f} (gen2 "
              f"{g['pause_ms_per_s'][2]:.3f}); longest gen0/1/2 "
              + "/".join(f"{m:.2f}" for m in g["max_ms"]) + f" ms; pauses over 1 ms in the "
              f"window: {g['over_1ms']}")
    print(f"{'own %':>6} {'total %':>7}  function")
    for name, own_pct, total_pct in rows:
        print(f"{own_pct:6.1f} {total_pct:7.1f}  {name}")


@contextmanager
def node_session(checkout: Path, backend: str, gc_file: Path):
    """The node of ``checkout`` (its emulator too, for the controller) with the GC probe on its
    path; yields (driver, calls, extra pids)."""
    from support import ros_harness
    from .state_topics import TOPICS
    ros_harness.NODE = checkout / "scripts" / "jaka_driver_node"
    saved = dict(os.environ)
    os.environ["PYTHONPATH"] = os.pathsep.join([str(PROBE_SITE), saved.get("PYTHONPATH", "")])
    try:
        with ExitStack() as stack:
            extra = {}
            params = dict(backend="sim", model="zu5")
            if backend == "controller":
                emulator = _emulator(stack, checkout)
                extra["emulator"] = emulator.proc.pid
                params = dict(backend="controller", model="zu5", ip="127.0.0.1",
                              command_port=emulator.command_port,
                              status_port=emulator.status_port)
            os.environ["JAKA_PROBE_GC"] = str(gc_file)     # the node's, not the emulator's
            driver = ros_session.start_driver(stack, "node_profile", **params)
            calls = ros_session.services(stack, driver)
            for name, msg_type in TOPICS:
                ros_session.recorder(stack, driver.name(name), msg_type)
            time.sleep(1.0)
            yield driver, calls, extra
    finally:
        os.environ.clear()
        os.environ.update(saved)


def _emulator(stack: ExitStack, checkout: Path):
    """``checkout``'s emulator, as bench's controller group starts it (a packet every 8 ms,
    the arm enabled)."""
    from jaka_driver.emulator import process
    saved = process._SRC
    process._SRC = checkout / "src"
    try:
        emulator = process.EmulatorProcess("zu5", period=0.008, start="enabled")
        stack.callback(emulator.stop)
        emulator.start()
    finally:
        process._SRC = saved
    return emulator


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.node_profile",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--windows", default=",".join(SIM_WINDOWS + CONTROLLER_WINDOWS))
    parser.add_argument("--node", help="another checkout's scripts/jaka_driver_node")
    parser.add_argument("--against", help="a second checkout (its root) profiled in turn")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--top", type=int, default=12)
    parser.add_argument("--spy-emulator", action="store_true",
                        help="on the controller windows, sample the emulator instead of the node")
    parser.add_argument("--sched", action="store_true",
                        help="perf sched record each window: scheduling delay per thread")
    args = parser.parse_args(argv)
    windows = [w.strip() for w in args.windows.split(",") if w.strip()]
    unknown = set(windows) - set(SIM_WINDOWS + CONTROLLER_WINDOWS)
    if unknown:
        parser.error(f"unknown windows {sorted(unknown)}")
    first = Path(args.node).resolve().parents[1] if args.node else ROOT
    checkouts = [first] + ([Path(args.against).resolve()] if args.against else [])
    gc_file = Path(tempfile.mkdtemp(prefix="node_profile_gc_")) / "gc.json"
    with ExitStack() as stack:
        ros_session.start_ros(stack)
        for backend, names in (("sim", SIM_WINDOWS), ("controller", CONTROLLER_WINDOWS)):
            chosen = [w for w in names if w in windows]
            if not chosen:
                continue
            for r in range(args.rounds):
                order = checkouts if r % 2 == 0 else checkouts[::-1]
                for checkout in order:
                    label = f"{checkout} (round {r + 1})"
                    print(f"\n# {backend} node of {label}; load {os.getloadavg()[0]:.2f}",
                          flush=True)
                    with node_session(checkout, backend, gc_file) as (driver, calls, extra):
                        probe = GcProbe(gc_file)
                        for window in chosen:
                            spied, others = driver.proc.pid, extra
                            if args.spy_emulator and "emulator" in extra:
                                spied, others = extra["emulator"], {"node": driver.proc.pid}
                                probe = None
                            with profiled(spied, probe, others, args.sched) as got:
                                measured = run_window(window, driver, calls, args.seconds)
                            report(label, window, got, measured, args.top)
                            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
