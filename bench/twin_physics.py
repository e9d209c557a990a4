"""Speed of the MuJoCo twin alone, without ROS and without real-time pacing.

Two numbers for the zu5 twin (``SimBackend`` built, its physics thread not started):

* ``mj_step`` alone on the twin's compiled model (MuJoCo's own cost: dynamics and contacts),
  and the same with contact detection switched off;
* the twin's full physics step, as its thread runs it: motion source every 8 ms cycle, the
  servo drive's computed-torque law, ``mj_step1``/``mj_step2``, the collision monitor hook.

Steps per second are counted over ``SECONDS`` of wall time each; the real-time factor is
steps/s × the 1 ms physics time step (RTF 50 = fifty times faster than the wall clock).
"""
from __future__ import annotations

import time

import mujoco

from jaka_driver.models import load_model
from jaka_driver.sim.backend import SimBackend
from jaka_driver.sim.twin_model import build_twin_model

from .profiling import describe, hot_functions
from .report import REPORT, Row, judged

SECONDS = 1.5
RTF_TARGET = 50.0


def _rate(step, seconds: float, batch: int = 200) -> float:
    """Calls of ``step()`` per second, measured in batches for ``seconds``."""
    n = 0
    t0 = time.perf_counter()
    while True:
        for _ in range(batch):
            step()
        n += batch
        elapsed = time.perf_counter() - t0
        if elapsed >= seconds:
            return n / elapsed


def run(model_name: str = "zu5", seconds: float = SECONDS) -> dict:
    backend = SimBackend(load_model(model_name))
    physics = backend.physics
    dt = physics.m.opt.timestep
    # A compiled copy: the contact switch below must not touch the backend's model.
    raw_model = build_twin_model(backend.model)
    raw_data = mujoco.MjData(raw_model)
    raw_data.qpos[:6] = physics.d.qpos[:6]
    mj_rate = _rate(lambda: mujoco.mj_step(raw_model, raw_data), seconds)
    # The same without contact detection: how much of MuJoCo's cost is collision checking.
    saved = raw_model.opt.disableflags
    raw_model.opt.disableflags = saved | mujoco.mjtDisableBit.mjDSBL_CONTACT
    try:
        free_rate = _rate(lambda: mujoco.mj_step(raw_model, raw_data), seconds / 2)
    finally:
        raw_model.opt.disableflags = saved
    # The loop's own step function: the unit of work its thread repeats 1000 times a second.
    twin_rate = _rate(lambda: physics._step(dt), seconds)
    hot = hot_functions(lambda: physics._step(dt), 5000)
    return {"model": model_name, "timestep_s": dt, "mj_step_per_s": mj_rate,
            "twin_step_per_s": twin_rate, "mj_step_no_contacts_per_s": free_rate, "mj_rtf": mj_rate * dt, "twin_rtf": twin_rate * dt,
            "profile": hot}


def rows(r: dict) -> list[Row]:
    group = "Twin physics (MuJoCo, no ROS)"
    return [
        Row(group, f"{r['model']}: mj_step alone (contacts on / off)",
            f"{r['mj_step_per_s'] / 1e3:.1f} k steps/s, RTF {r['mj_rtf']:.0f} / "
            f"{r['mj_step_no_contacts_per_s'] / 1e3:.0f} k steps/s", "report", REPORT, data=r),
        Row(group, f"{r['model']}: full twin step (servo law + MuJoCo + collision check)",
            f"{r['twin_step_per_s'] / 1e3:.1f} k steps/s, RTF {r['twin_rtf']:.0f}",
            f"report; RTF ≥ {RTF_TARGET:g}", judged(r["twin_rtf"] >= RTF_TARGET),
            note=("" if r["twin_rtf"] >= RTF_TARGET else
                  f"MuJoCo alone runs at RTF {r['mj_rtf']:.0f}; the rest of each 1 ms step is "
                  f"Python around it (cProfile, own time: {describe(r['profile'])}): the "
                  "servo law is a dozen numpy calls on 6-vectors per step, each ~1–2 µs of "
                  "overhead. Computing the law in MuJoCo (a position actuator with kp/kv "
                  "and gravity compensation, or an mjcb_control callback in C) and stepping "
                  "the 8 steps of a cycle with one mj_step(m, d, nstep=8) would leave only "
                  "MuJoCo's own cost — itself near the target with contacts on: collision "
                  "checking only the pairs that can touch, or once per 8 ms cycle, would "
                  "give the margin.")),
    ]
