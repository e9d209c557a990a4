"""Speed and tracking of the MuJoCo twin alone, without ROS and without real-time pacing.

For the zu5 twin (``SimBackend`` built, its physics thread not started):

* ``mj_step`` alone on the twin's compiled model (MuJoCo's own cost: dynamics, drives and
  contacts), and the same with contact detection switched off;
* the twin's full cycle, as its thread runs it: the drives' per-cycle set-up, one
  ``mj_step(m, d, nstep=8)``, the collision and overload checks, the motion source and the
  sample — counted in physics steps (8 per cycle);
* the drives' tracking: a 0.5 Hz sine of 0.5 rad/s peak on every joint streamed as servo
  targets, one per cycle; the error (rad) of each joint at the end of each cycle against that
  cycle's setpoint.

Steps per second are counted over ``SECONDS`` of thread CPU time each (the machine may be
shared: CPU time is what the twin costs, wall time would add other programs' share); the
real-time factor is steps/s × the 1 ms physics time step (RTF 150 = 150 times faster than
the wall clock, 6.7 % of a core to run in real time).
"""
from __future__ import annotations

import time

import mujoco
import numpy as np

from jaka_driver.models import load_model
from jaka_driver.sim.backend import SimBackend
from jaka_driver.sim.motions import ServoTarget
from jaka_driver.sim.twin_model import build_twin_model

from .profiling import describe, hot_functions
from .report import REPORT, Row, judged

SECONDS = 1.5
RTF_TARGET = 150.0
SINE_PEAK_RAD_S = 0.5
SINE_HZ = 0.5
SINE_S = 4.0


def _rate(step, seconds: float, batch: int = 200) -> float:
    """Calls of ``step()`` per second, measured in batches for ``seconds``."""
    n = 0
    t0 = time.thread_time()
    while True:
        for _ in range(batch):
            step()
        n += batch
        elapsed = time.thread_time() - t0
        if elapsed >= seconds:
            return n / elapsed


def sine_tracking(model_name: str = "zu5", seconds: float = SINE_S) -> dict:
    """Largest and RMS error (rad) of the joints at the end of each cycle against that
    cycle's setpoint, streaming a sine of ``SINE_PEAK_RAD_S`` peak at ``SINE_HZ`` on every
    joint (the first second, while the stream starts from rest, is left out)."""
    backend = SimBackend(load_model(model_name))
    physics = backend.physics
    cycle = physics.cycle
    center = physics.servo.setpoint.copy()
    amplitude = SINE_PEAK_RAD_S / (2 * np.pi * SINE_HZ)
    target = ServoTarget(center)
    physics.switch(target)
    errors, previous = [], None
    for k in range(int(round(seconds / cycle))):
        q = center + amplitude * np.sin(2 * np.pi * SINE_HZ * k * cycle)
        target.set(q)
        physics._cycle()        # steps the setpoint chosen last cycle, then chooses q
        if previous is not None and k * cycle >= 1.0:
            errors.append(physics.d.qpos[:6] - previous)
        previous = q
    e = np.abs(np.array(errors))
    return {"peak_rad_s": SINE_PEAK_RAD_S, "hz": SINE_HZ, "max_rad": float(e.max()),
            "rms_rad": float(np.sqrt(np.mean(e ** 2))), "per_joint_max_rad": e.max(0).tolist()}


def run(model_name: str = "zu5", seconds: float = SECONDS) -> dict:
    backend = SimBackend(load_model(model_name))
    physics = backend.physics
    dt = physics.m.opt.timestep
    steps = physics.steps_per_cycle
    # A compiled copy: the contact switch below must not touch the backend's model.
    raw_model = build_twin_model(backend.model)
    raw_data = mujoco.MjData(raw_model)
    raw_data.qpos[:6] = physics.d.qpos[:6]
    raw_data.act[:6] = physics.d.qpos[:6]        # the drives hold the arm where it stands
    mj_rate = _rate(lambda: mujoco.mj_step(raw_model, raw_data), seconds)
    # The same without contact detection: how much of MuJoCo's cost is collision checking.
    saved = raw_model.opt.disableflags
    raw_model.opt.disableflags = saved | mujoco.mjtDisableBit.mjDSBL_CONTACT
    try:
        free_rate = _rate(lambda: mujoco.mj_step(raw_model, raw_data), seconds / 2)
    finally:
        raw_model.opt.disableflags = saved
    # The loop's own cycle: the unit of work its thread repeats 125 times a second.
    twin_rate = steps * _rate(physics._cycle, seconds, batch=25)
    hot = hot_functions(physics._cycle, 1000)
    return {"model": model_name, "timestep_s": dt, "mj_step_per_s": mj_rate,
            "twin_step_per_s": twin_rate, "mj_step_no_contacts_per_s": free_rate,
            "mj_rtf": mj_rate * dt, "twin_rtf": twin_rate * dt, "profile": hot,
            "sine": sine_tracking(model_name)}


def rows(r: dict) -> list[Row]:
    group = "Twin physics (MuJoCo, no ROS)"
    return [
        Row(group, f"{r['model']}: mj_step alone (contacts on / off)",
            f"{r['mj_step_per_s'] / 1e3:.1f} k steps/s, RTF {r['mj_rtf']:.0f} / "
            f"{r['mj_step_no_contacts_per_s'] / 1e3:.0f} k steps/s", "report", REPORT, data=r),
        Row(group, f"{r['model']}: full twin cycle (drives set-up + mj_step × 8 + checks), "
            "per step", f"{r['twin_step_per_s'] / 1e3:.1f} k steps/s, RTF {r['twin_rtf']:.0f}",
            f"report; RTF ≥ {RTF_TARGET:g}", judged(r["twin_rtf"] >= RTF_TARGET),
            note=("" if r["twin_rtf"] >= RTF_TARGET else
                  f"MuJoCo alone runs at RTF {r['mj_rtf']:.0f} (one mj_step call a step); "
                  "the cycle makes one call for 8 steps, so the Python around it (cProfile, "
                  f"own time: {describe(r['profile'])}) is paid once per 8 ms. The rest "
                  "is MuJoCo's own step on this machine at the time of the run (compare "
                  "the row above, measured in the same run).")),
        Row(group, f"{r['model']}: drives' tracking of a {r['sine']['hz']:g} Hz sine of "
            f"{r['sine']['peak_rad_s']:g} rad/s peak, error at each cycle's end",
            f"max {r['sine']['max_rad'] * 1e3:.4f} mrad, RMS {r['sine']['rms_rad'] * 1e3:.4f} "
            "mrad (all joints)", "report", REPORT, data=r["sine"]),
    ]
