"""The twin's cameras (docs/twin.md "Cameras"), beside the sim group's rows:

1. **render time** per frame, p50 / p99, of colour + depth at 640 × 480 and 1280 × 720, in this
   process (the renderer the node uses, EGL — llvmpipe on a machine without a GPU), no ROS;
2. through ROS, on the zu5 twin on the wall clock (as a user runs it) in a cell with a fixed
   camera ``vga`` (640 × 480, 10 Hz) and ``hd`` (1280 × 720, 10 Hz), three windows of the same
   length — no camera subscribed, ``vga`` subscribed, ``hd`` subscribed — each taken as
   :data:`ROUNDS` shorter windows in turn (the machine's neighbours change within minutes;
   side by side, each condition gets its share of them). In each: the state
   topics' rows (bench.state_topics: rate, inter-arrival, sample age), node CPU (% of one
   core) and, beside it, the renderer's process's (jaka_driver.sim.camera_process); with a camera, its frame rate against the asked one (± 10 %), and the frames' sample
   age at publication (receipt time − ``header.stamp``, the time of the cycle the frame shows:
   its rendering, publication and one hop over TCP). The issue's target: with ``vga``
   subscribed the state topics keep 125 Hz and their inter-arrival p99 is at most 1.05 × the
   window without a camera.
"""
from __future__ import annotations

import struct
import tempfile
import time
from contextlib import ExitStack
from pathlib import Path

import numpy as np
import yaml

from . import ros_session, state_topics
from .proc_meter import CpuWindow, MachineWindow
from .report import REPORT, Row, judged
from .stats import fmt, summary

GROUP = "Cameras of the twin (zu5, fixed cameras, through ROS)"
CAMERAS = {"vga": (640, 480), "hd": (1280, 720)}
RATE_HZ, RATE_TOL = 10.0, 0.10           # asked, and the issue's ± 10 %
INTERARRIVAL_RATIO = 1.05                # state topics' p99 with a camera / without
RENDER_FRAMES = 100


def cell(folder: Path) -> str:
    """A scene file: a table and a part, both cameras 1 m above the table looking down."""
    data = {"obstacles": [
        {"name": "table", "type": "box", "size": [0.3, 0.3, 0.05], "pos": [0.0, -0.55, 0.05]},
        {"name": "part", "type": "box", "size": [0.04, 0.03, 0.02], "pos": [0.1, -0.62, 0.12]}],
        "cameras": [{"name": name, "width": w, "height": h, "fovy": 60, "rate": RATE_HZ,
                     "pos": [0.0, -0.55, 1.1], "euler": [0, float(np.pi / 2), 0],
                     "point_cloud": False} for name, (w, h) in CAMERAS.items()]}
    path = folder / "bench_cameras.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


def render_times(scene: str, frames: int = RENDER_FRAMES) -> dict:
    """Wall seconds per colour + depth frame of each camera, the arm moving a little between
    frames (so no frame is a copy of the one before)."""
    from jaka_driver.common.camera_spec import cameras_of_scene
    from jaka_driver.common.models import load_model
    from jaka_driver.sim.camera_render import CameraRenderer
    model = load_model("zu5")
    renderer = CameraRenderer(model, cameras_of_scene(scene), scene)
    out = {}
    try:
        for name in CAMERAS:
            times = []
            for i in range(frames):
                q = model.home + np.array([0.001 * i, 0, 0, 0, 0, 0])
                t0 = time.perf_counter()
                renderer.render(name, q)
                times.append(time.perf_counter() - t0)
            out[name] = summary(np.array(times[1:]), 1e3)        # the first one warms up
    finally:
        renderer.close()
    return out


def renderer_pid(node_pid: int) -> int | None:
    """The node's camera renderer process (jaka_driver.sim.camera_process), if it runs."""
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            stat = (proc / "stat").read_text()
            parent = int(stat[stat.rindex(")") + 2:].split()[1])
            if parent == node_pid and b"camera_process" in (proc / "cmdline").read_bytes():
                return int(proc.name)
        except (OSError, ValueError):
            continue            # ended meanwhile
    return None


class FrameStamps:
    """(receipt time, header stamp) of each message of an image topic — the frames themselves
    are neither kept nor read: 30 s of 640 × 480 colour + depth is 630 MB, whose allocation in
    this process slowed the state topics' subscribers beside it, and deserialising a frame
    copies its megabytes with the interpreter lock held, which the state topics' receiving
    threads here would wait behind. The stamp is read from the message's bytes (``AnyMsg``;
    a ``std_msgs/Header`` first: seq, then the stamp's secs and nsecs)."""

    def __init__(self, stack: ExitStack, topic: str):
        import rospy
        self.stamps: list[tuple[float, float]] = []
        sub = rospy.Subscriber(topic, rospy.AnyMsg, self._on, queue_size=10, tcp_nodelay=True)
        stack.callback(sub.unregister)

    def _on(self, msg) -> None:
        secs, nsecs = struct.unpack_from("<II", msg._buff, 4)
        self.stamps.append((time.time(), secs + nsecs * 1e-9))


ROUNDS = 3                 # the windows taken in turn: none, vga, hd, none, vga, hd, ...


def _window(driver, seconds: float, camera: str | None) -> dict:
    """State topics (raw), node CPU, the renderer's CPU and (with ``camera``) its frames over
    one window."""
    with ExitStack() as stack:
        frames = None
        if camera is not None:
            frames = FrameStamps(stack, f"/{camera}/image_raw")
            depth = FrameStamps(stack, f"/{camera}/depth/image_raw")
            ros_session.wait_until(lambda: depth.stamps, 30.0)
            time.sleep(1.0)                  # the renderer warmed up
        else:
            time.sleep(1.0)                  # the camera before has stopped streaming
        renderer = renderer_pid(driver.proc.pid)
        with MachineWindow() as machine, CpuWindow(driver.proc.pid) as cpu, \
                CpuWindow(renderer or driver.proc.pid) as render_cpu:
            t0 = time.time()
            topics = state_topics.record(driver, seconds)
            t1 = time.time()
        out = {"topics": topics, "cpu": cpu.as_dict(),
               "renderer_cpu": render_cpu.as_dict() if renderer else None,
               "machine_percent": machine.percent}
        if frames is not None:
            out["frames"] = [(t, s) for t, s in list(frames.stamps) if t0 <= t <= t1]
    return out


def _mean_cpu(parts: list[dict]) -> dict:
    """One window's CPU figures from several: time-weighted mean %, the last RSS."""
    total = sum(p["window_s"] for p in parts)
    return {**parts[-1], "window_s": total,
            "cpu_percent": sum(p["cpu_percent"] * p["window_s"] for p in parts) / total}


def _merged(parts: list[dict]) -> dict:
    """The windows of one condition as one: topics pooled (state_topics.analyse_windows),
    CPU time-weighted, frame rate over the summed spans, ages pooled."""
    out = {"topics": state_topics.analyse_windows([p["topics"] for p in parts]),
           "cpu": _mean_cpu([p["cpu"] for p in parts]),
           "renderer_cpu": (_mean_cpu([p["renderer_cpu"] for p in parts])
                            if all(p["renderer_cpu"] for p in parts) else None),
           "machine_percent": float(np.mean([p["machine_percent"] for p in parts]))}
    if "frames" in parts[0]:
        got = [p["frames"] for p in parts]
        count = sum(len(g) for g in got)
        span = sum(g[-1][0] - g[0][0] for g in got if len(g) > 1)
        out["frames"] = {"count": count,
                         "rate_hz": sum(len(g) - 1 for g in got if len(g) > 1) / span
                         if span > 0 else 0.0,
                         "age_ms": summary(np.array([t - s for g in got for t, s in g]), 1e3)}
    return out


def run(driver, seconds: float, log=print) -> dict:
    """``seconds`` per condition, in :data:`ROUNDS` windows taken in turn, so that the
    machine's slow changes (its neighbours) fall on every condition alike."""
    parts: dict[str, list] = {}
    for round_ in range(ROUNDS):
        for camera in (None,) + tuple(CAMERAS):
            label = f"{camera} subscribed" if camera else "no camera subscribed"
            log(f"cameras: round {round_ + 1} of {ROUNDS}, {label}, {seconds / ROUNDS:g} s")
            parts.setdefault(label, []).append(_window(driver, seconds / ROUNDS, camera))
    return {label: _merged(p) for label, p in parts.items()}


def rows(renders: dict, windows: dict) -> list[Row]:
    out = []
    for name, (w, h) in CAMERAS.items():
        r = renders[name]
        out.append(Row(GROUP, f"render time p50 / p99, colour + depth {w}×{h}",
                       f"{fmt(r['p50'])} / {fmt(r['p99'])} ms", "report", REPORT, data=r))
    for label, win in windows.items():
        out += state_topics.rows(GROUP, label, win["topics"],
                                 machine_percent=win["machine_percent"])
        out.append(Row(GROUP, f"node CPU, {label}", f"{win['cpu']['cpu_percent']:.1f} %",
                       "report", REPORT, data=win["cpu"]))
        if win.get("renderer_cpu"):
            out.append(Row(GROUP, f"renderer process CPU (SCHED_IDLE), {label}",
                           f"{win['renderer_cpu']['cpu_percent']:.1f} %", "report", REPORT,
                           data=win["renderer_cpu"]))
        f = win.get("frames")
        if f is not None:
            ok = abs(f["rate_hz"] - RATE_HZ) <= RATE_TOL * RATE_HZ
            out.append(Row(GROUP, f"frame rate, {label}", f"{f['rate_hz']:.2f} Hz "
                           f"({f['count']} frames)", f"{RATE_HZ:g} Hz ± {RATE_TOL:.0%}",
                           judged(ok), "" if ok else "frames were dropped: the node's log "
                           "says how many and how long a frame took to render", data=f))
            a = f["age_ms"]
            out.append(Row(GROUP, f"frame sample age p50 / p99, {label}",
                           f"{fmt(a['p50'])} / {fmt(a['p99'])} ms", "report", REPORT,
                           data=a))
    base = windows["no camera subscribed"]["topics"]
    with_vga = windows["vga subscribed"]["topics"]
    for topic in base:
        p0, p1 = base[topic]["interarrival_ms"]["p99"], with_vga[topic]["interarrival_ms"]["p99"]
        ok = p0 is not None and p1 is not None and p1 <= INTERARRIVAL_RATIO * p0
        out.append(Row(GROUP, f"{topic} inter-arrival p99, vga subscribed / none",
                       f"{fmt(p1)} / {fmt(p0)} ms", f"≤ {INTERARRIVAL_RATIO:g} ×",
                       judged(ok)))
    return out


def measure(stack: ExitStack, seconds: float, log=print) -> list[Row]:
    """The whole group: render times in-process, then the three windows on a node."""
    folder = Path(stack.enter_context(tempfile.TemporaryDirectory()))
    scene = cell(folder)
    log("cameras: render times, in-process")
    renders = render_times(scene)
    log("cameras: node starting")
    driver = ros_session.start_driver(stack, "bench_cameras", backend="sim", model="zu5",
                                      scene=scene)
    return rows(renders, run(driver, seconds, log))
