"""Trajectory recording on the zu5 twin:

1. **a known path** (RobotDriver on the twin in simulated time, no ROS): a 100 mm straight line
   along base x at 50 mm/s, recorded with 5 mm / 2° thresholds; the count of kept points (the
   rule keeps one each time the tool has gone 5 mm, so 100 / 5 + 1 = 21 within one cycle's
   travel), the replay's largest distance from a kept point and from the recorded line
   (the replay of ``track/<name>`` through the program engine, sampled every cycle);
2. **node CPU while recording** (the node on the wall clock, through ROS): the same slow joint
   move twice, J1 −0.6 rad at 0.1 rad/s, once not recording and once recording at JAKA's
   default thresholds (0.1 mm, 0.2°: a point kept almost every cycle) — the recording's own
   cost is the difference, a pose from the measured joints each 8 ms cycle.
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from jaka_driver.backend import ProgramState
from jaka_driver.common.models import load_model
from jaka_driver.programs.track import TrackFolder

from .proc_meter import CpuWindow, MachineWindow
from .report import REPORT, Row, judged

GROUP = "Trajectory recording (zu5 twin)"
LINE_MM, SPEED_MM_S = 100.0, 50.0
XYZ_MM, RPY_DEG = 5.0, 2.0
#: targets: the issue's replay check, and what a recording may add to the node's CPU
REPLAY_MM = XYZ_MM + 0.5
RECORDING_CPU_POINTS = 2.0          # % of one core over the same move not recording
MOVE_RAD, MOVE_SPEED = 0.6, 0.1


def _samples(driver, until, limit: float = 120.0) -> list:
    out, last, start = [], driver.state().stamp, driver.clock.now()
    while not until() and driver.clock.now() - start < limit:
        driver.clock.sleep(0.08)
        for st in driver.states_since(last):
            out.append(st)
            last = st.stamp
    return out


def known_path(log=print) -> dict:
    """Record the line, replay it: the kept points, the line's and the replay's TCP (mm)."""
    from jaka_driver.driver import RobotDriver
    from jaka_driver.programs import FolderPrograms
    from jaka_driver.sim import SimBackend
    folder = tempfile.mkdtemp(prefix="bench_recording_")
    driver = RobotDriver(SimBackend(load_model("zu5"), sim_time=True, real_time_factor=0,
                                    programs=FolderPrograms(folder)))
    driver.start()
    try:
        with driver.clock.hold():
            rec = driver.recording
            for result in (rec.set_config(XYZ_MM, RPY_DEG, SPEED_MM_S, 500.0),
                           rec.set_sample_mode(True, "line")):
                if not result.ok:
                    raise RuntimeError(result.message)
            start = driver.get_fk(list(driver.state().joint_position)).value
            end = list(start)
            end[0] += LINE_MM
            log(f"  recording a {LINE_MM:g} mm line at {SPEED_MM_S:g} mm/s")
            moved = driver.linear_move(end, SPEED_MM_S, 500.0)
            if not moved.ok:
                raise RuntimeError(moved.message)
            rec.set_sample_mode(False)
            if not rec.generate("line").ok or not driver.programs.load("track/line").ok:
                raise RuntimeError("generate or load refused")
            home = driver.joint_move(list(driver.model.home), 1.0, 0)
            if not home.ok:
                raise RuntimeError(home.message)
            driver.programs.play()
            replay = _samples(driver, lambda: driver.programs.status().state
                              == ProgramState.IDLE)
        status = driver.programs.status()
        if status.error:
            raise RuntimeError(status.error)
        kept = TrackFolder(Path(folder)).load("line")
        return {"kept": np.array([p.pose_mm[:3] for p in kept]),
                "line": (np.array(start[:3]), np.array(end[:3])),
                "replay": np.array([s.tcp_pose[:3, 3] * 1000.0 for s in replay])}
    finally:
        driver.shutdown()


def recording_cpu(driver, calls, log=print) -> dict:
    """The node's CPU over the same slow joint move, not recording and recording."""
    from jaka_msgs.srv import Move
    from jaka_driver_msgs.srv import SetTrajConfig, SetTrajSampleMode
    home = list(load_model("zu5").home)
    away = list(home)
    away[0] -= MOVE_RAD
    windows = {}
    for label, record in (("not recording", False), ("recording", True)):
        calls("joint_move", Move, pose=home, mvvelo=1.0, mvacc=2.0)
        if record:
            calls("set_traj_config", SetTrajConfig, xyz_interval=0.1, rpy_interval=0.2,
                  vel=25.0, acc=100.0)
            calls("set_traj_sample_mode", SetTrajSampleMode, start=True, filename="bench")
        log(f"  joint move {MOVE_RAD:g} rad at {MOVE_SPEED:g} rad/s, {label}")
        with MachineWindow() as machine, CpuWindow(driver.proc.pid) as cpu:
            reply = calls("joint_move", Move, pose=away, mvvelo=MOVE_SPEED, mvacc=1.0)
        if record:
            stopped = calls("set_traj_sample_mode", SetTrajSampleMode, start=False,
                            filename="")
            windows["stop_message"] = stopped.message
        if reply.ret != 1:
            raise RuntimeError(f"joint_move: {reply.message}")
        windows[label] = {**cpu.as_dict(), "machine_percent": machine.percent}
    return windows


def rows(path: dict, cpu: dict | None) -> list[Row]:
    out = []
    kept, replay = path["kept"], path["replay"]
    expected = LINE_MM / XYZ_MM + 1
    steps = np.linalg.norm(np.diff(kept, axis=0), axis=1)
    ok = abs(len(kept) - expected) <= 1
    out.append(Row(GROUP, f"kept points of a {LINE_MM:g} mm line at {SPEED_MM_S:g} mm/s, "
                   f"{XYZ_MM:g} mm / {RPY_DEG:g}° thresholds",
                   f"{len(kept)} points, steps {steps.min():.3f}–{steps.max():.3f} mm",
                   f"{expected:g} ± 1 (one each {XYZ_MM:g} mm)", judged(ok), "",
                   data={"kept": int(len(kept)), "step_min_mm": float(steps.min()),
                         "step_max_mm": float(steps.max())}))
    to_kept = max(float(np.min(np.linalg.norm(replay - p, axis=1))) for p in kept)
    a, b = path["line"]
    u = (b - a) / np.linalg.norm(b - a)
    along = np.clip((replay - a) @ u, 0.0, np.linalg.norm(b - a))
    from_line = np.linalg.norm(replay - (a + np.outer(along, u)), axis=1)
    started = int(np.argmin(np.linalg.norm(replay - kept[0], axis=1)))
    off_line = float(from_line[started:].max())
    out.append(Row(GROUP, "its replay (track/line through the program engine): farthest from "
                   "a kept point / from the recorded line after the first point",
                   f"{to_kept:.3f} mm / {off_line:.3f} mm ({len(replay)} cycles)",
                   f"≤ {REPLAY_MM:g} mm from every kept point", judged(to_kept <= REPLAY_MM),
                   "", data={"to_kept_mm": to_kept, "off_line_mm": off_line}))
    if cpu is not None:
        off, on = cpu["not recording"], cpu["recording"]
        added = on["cpu_percent"] - off["cpu_percent"]
        for label, w in (("not recording", off), ("recording", on)):
            out.append(Row(GROUP, f"node CPU over a {MOVE_RAD:g} rad joint move at "
                           f"{MOVE_SPEED:g} rad/s, {label}",
                           f"{w['cpu_percent']:.1f} % of one core; machine "
                           f"{w['machine_percent']:.0f} % over {w['window_s']:.1f} s",
                           "report" if label == "not recording" else
                           f"≤ not recording + {RECORDING_CPU_POINTS:g} points",
                           REPORT if label == "not recording" else
                           judged(added <= RECORDING_CPU_POINTS),
                           "" if label == "not recording" else
                           f"{added:+.1f} points; {cpu.get('stop_message', '')}", data=w))
    return out

