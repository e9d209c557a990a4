"""linear_move: how far does the measured TCP stray from the ideal straight line?

``N_LINES`` lines, each from a random start configuration (:mod:`bench.poses`) in a random
direction, ``LENGTH_MM`` long, orientation kept; a line is used only if the driver's own
planner (``plan_linear_move`` with the project's IK, as the twin runs it) accepts it and it
stays ``MIN_Z_M`` above the floor. The arm is brought to the start with joint_move and left
to settle; then linear_move runs at ``SPEED_MM_S``. Deviation = distance (mm) of each
``tool_position`` sample received during the move from the segment start → target, where
start is the TCP pose of the start configuration (what the planner starts from).
"""
from __future__ import annotations

import time

import numpy as np
from geometry_msgs.msg import TwistStamped

from jaka_msgs.srv import ClearErr, Move
from jaka_driver.common.transforms import matrix_to_pose_mm
from jaka_driver.kinematics import Kinematics
from jaka_driver.motion.linear_path import PlanningError, plan_linear_move

from . import ros_session
from .poses import HOME, PoseSampler
from .report import Row, at_most, judged

N_LINES = 20
LENGTH_MM = (80.0, 200.0)
SPEED_MM_S = 100.0
ACCEL_MM_S2 = 500.0
MIN_Z_M = 0.15
SPREAD_RAD = 0.6
TARGET_MM = 0.1
SETTLE_S = 0.4


def _lines(model, n: int):
    """``n`` (start q, start pose, target pose) the planner accepts."""
    kin = Kinematics(model)
    sampler = PoseSampler(model, seed=66)
    rng = sampler.rng

    def ik(T, seed):
        result = kin.ik(T, seed=seed)
        return result.q if result.success else None

    out = []
    while len(out) < n:
        q0 = sampler.near_home(SPREAD_RAD)
        start = kin.flange_pose(q0)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        goal = start.copy()
        goal[:3, 3] += direction * rng.uniform(*LENGTH_MM) / 1000.0
        if min(start[2, 3], goal[2, 3]) < MIN_Z_M:
            continue
        try:
            plan_linear_move(start, goal, SPEED_MM_S / 1000, ACCEL_MM_S2 / 1000, q0, ik,
                             model.lower, model.upper, model.max_velocity)
        except PlanningError:
            continue
        out.append((q0, start, goal))
    return out


def _distance_from_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    s = np.clip((points - a) @ ab / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(points - (a + s[:, None] * ab), axis=1), s


def run(model, driver, calls, n: int = N_LINES) -> dict:
    lines = []
    rec = ros_session.Recorder(driver.name("tool_position"), TwistStamped)
    try:
        for q0, start, goal in _lines(model, n):
            reply = calls("joint_move", Move, pose=q0.tolist(), mvvelo=2.0, mvacc=8.0)
            if reply.ret != 1:
                calls("clear_err", ClearErr)
                lines.append({"ret": reply.ret, "message": f"reaching the start: {reply.message}"})
                continue
            time.sleep(SETTLE_S)
            pose = matrix_to_pose_mm(goal)
            t0 = time.time()
            reply = calls("linear_move", Move, pose=pose.tolist(), mvvelo=SPEED_MM_S,
                          mvacc=ACCEL_MM_S2, coord_mode=1)
            t1 = time.time()
            samples = [m for t, m in rec.since(t0) if t <= t1]
            p = np.array([[m.twist.linear.x, m.twist.linear.y, m.twist.linear.z]
                          for m in samples]) * 1000.0
            a, b = start[:3, 3] * 1000.0, goal[:3, 3] * 1000.0
            dev, s = _distance_from_segment(p, a, b) if len(p) else (np.zeros(0), np.zeros(0))
            lines.append({"ret": reply.ret, "message": reply.message, "length_mm":
                          float(np.linalg.norm(b - a)), "samples": len(p),
                          "max_dev_mm": float(dev.max()) if dev.size else float("nan"),
                          "end_error_mm": float(np.linalg.norm(p[-1] - b)) if len(p) else None,
                          "deviation_mm": dev, "fraction": s, "duration_s": t1 - t0})
            if reply.ret != 1:
                calls("clear_err", ClearErr)
    finally:
        rec.close()
    calls("joint_move", Move, pose=HOME.tolist(), mvvelo=2.0, mvacc=8.0)
    return {"lines": lines}


def rows(r: dict) -> list[Row]:
    group = "Motion on the twin (through ROS)"
    done = [ln for ln in r["lines"] if ln["ret"] == 1]
    failed = len(r["lines"]) - len(done)
    devs = np.array([ln["max_dev_mm"] for ln in done])
    worst = float(devs.max()) if devs.size else float("nan")
    passed = bool(devs.size) and not failed and worst <= TARGET_MM
    note = ""
    if devs.size and worst > TARGET_MM:
        note = (f"{int(np.sum(devs > TARGET_MM))} of {len(done)} lines exceed "
                f"{TARGET_MM:g} mm (median of the per-line maxima {np.median(devs):.3f} mm). "
                "The plan itself is exact (IK every 8 ms on the line); the measured TCP "
                "strays because the servo drive follows the joint setpoints with a lag and "
                "the joint-space interpolation between two 8 ms setpoints bows off the "
                "line. Stiffer drives / acceleration feed-forward in the twin's servo law "
                "(or a lag-compensated setpoint) would close it.")
    if failed:
        note += f" {failed} lines failed: " + "; ".join(
            ln["message"] for ln in r["lines"] if ln["ret"] != 1)
    return [Row(group, f"linear_move max TCP deviation from the line, {SPEED_MM_S:g} mm/s",
                f"worst {worst:.4f} mm, median {np.median(devs):.4f} mm "
                f"({len(done)} lines of {LENGTH_MM[0]:g}–{LENGTH_MM[1]:g} mm)"
                if devs.size else "no line ran",
                f"≤ {TARGET_MM:g} mm", judged(passed), note.strip(),
                data={"max_dev_mm": devs,
                      "end_error_mm": [ln["end_error_mm"] for ln in done]},
                bounds=at_most(worst if devs.size else None, TARGET_MM, "mm", "worst"))]
