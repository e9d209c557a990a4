"""Speed and tracking of the MuJoCo twin alone, without ROS and without real-time pacing.

For the zu5 twin (``SimBackend`` built, its physics thread not started):

* ``mj_step(m, d, nstep=8)`` alone on copies of the twin's model and data (MuJoCo's own cost:
  dynamics, drives and contact detection, at the twin's start pose), and the same with
  contact detection switched off;
* the twin's full cycle, as its thread runs it: the drives' per-cycle set-up, one
  ``mj_step(m, d, nstep=8)``, the collision and overload checks, the motion source and the
  sample — counted in physics steps (8 per cycle); the row says whether the compiled cycle
  (sim/joint_drives.c) or its numpy fallback ran;
* the drives' tracking: a 0.5 Hz sine of 0.5 rad/s peak on every joint streamed as servo
  targets, one per cycle; the error (rad) of each joint at the end of each cycle against that
  cycle's setpoint.

Steps per second are counted in thread CPU time (the machine may be shared: CPU time is what
the twin costs, wall time would add other programs' share), ``SECONDS`` for each kind of
step in ``ROUNDS`` rounds that take turns, and the best round is kept; the
real-time factor is steps/s × the 1 ms physics time step (RTF 150 = 150 times faster than
the wall clock, 6.7 % of a core to run in real time).
"""
from __future__ import annotations

import copy
import time

import mujoco
import numpy as np

from jaka_driver.common.models import load_model
from jaka_driver.sim import SimBackend
from jaka_driver.sim.motions import ServoTarget

from .profiling import describe, hot_functions
from .report import REPORT, Row, at_least, judged

SECONDS = 1.5
ROUNDS = 10
RTF_TARGET = 150.0
SINE_PEAK_RAD_S = 0.5
SINE_HZ = 0.5
SINE_S = 4.0


def _best_rates(steps: dict, seconds: float, rounds: int = ROUNDS, batch: int = 25) -> dict:
    """Calls per second of each ``steps[name]()``, the best of ``rounds`` rounds in which the
    steps take turns (each round runs every step for ``seconds / rounds`` of CPU time). On a
    shared machine other programs only ever slow a round down: taking turns puts every step
    under the same conditions, and the best round is the closest to the step's own cost."""
    best = dict.fromkeys(steps, 0.0)
    for _ in range(rounds):
        for name, step in steps.items():
            n = 0
            t0 = time.thread_time()
            while True:
                for _ in range(batch):
                    step()
                n += batch
                elapsed = time.thread_time() - t0
                if elapsed >= seconds / rounds:
                    break
            best[name] = max(best[name], n / elapsed)
    return best


def sine_tracking(model_name: str = "zu5", seconds: float = SINE_S) -> dict:
    """Largest and RMS error (rad) of the joints at the end of each cycle against that
    cycle's setpoint, streaming a sine of ``SINE_PEAK_RAD_S`` peak at ``SINE_HZ`` on every
    joint (the first second, while the stream starts from rest, is left out)."""
    backend = SimBackend(load_model(model_name))
    physics = backend._physics
    cycle = physics.cycle
    center = physics.servo.setpoint.copy()
    amplitude = SINE_PEAK_RAD_S / (2 * np.pi * SINE_HZ)
    target = ServoTarget(center, physics)
    physics.switch(target)
    errors, previous = [], None
    for k in range(int(round(seconds / cycle))):
        q = center + amplitude * np.sin(2 * np.pi * SINE_HZ * k * cycle)
        target.set(q)
        physics.step_cycle()        # steps the setpoint chosen last cycle, then chooses q
        if previous is not None and k * cycle >= 1.0:
            errors.append(physics.d.qpos[:6] - previous)
        previous = q
    e = np.abs(np.array(errors))
    return {"peak_rad_s": SINE_PEAK_RAD_S, "hz": SINE_HZ, "max_rad": float(e.max()),
            "rms_rad": float(np.sqrt(np.mean(e ** 2))), "per_joint_max_rad": e.max(0).tolist()}


def run(model_name: str = "zu5", seconds: float = SECONDS) -> dict:
    backend = SimBackend(load_model(model_name))
    physics = backend._physics
    dt = physics.m.opt.timestep
    steps = physics.steps_per_cycle
    # MuJoCo alone on copies of the twin's model and data, a few cycles in (the drives' gains,
    # reference and feed-forward written, the arm held at its start pose with no contact), so
    # the copies keep standing where the twin stands; stepped as the twin steps them, 8 steps a
    # call. (A freshly compiled model with no drive set-up sags onto the floor: its contacts
    # and constraint solve cost twice as much and are not what the twin pays.)
    for _ in range(10):
        physics.step_cycle()
    raw_model, raw_data = copy.deepcopy(physics.m), copy.deepcopy(physics.d)
    # The same without contact detection: how much of MuJoCo's cost is collision checking.
    free_model, free_data = copy.deepcopy(raw_model), copy.deepcopy(raw_data)
    free_model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    # The loop's own cycle (physics._cycle): the unit of work its thread repeats 125 times a
    # second.
    rates = _best_rates({
        "mj": lambda: mujoco.mj_step(raw_model, raw_data, nstep=steps),
        "free": lambda: mujoco.mj_step(free_model, free_data, nstep=steps),
        "twin": physics._cycle}, seconds)
    mj_rate, free_rate, twin_rate = (steps * rates[k] for k in ("mj", "free", "twin"))
    contacts = int(raw_data.ncon)
    hot = hot_functions(physics._cycle, 1000)
    return {"model": model_name, "timestep_s": dt, "mj_step_per_s": mj_rate,
            "twin_step_per_s": twin_rate, "mj_step_no_contacts_per_s": free_rate,
            "contacts_at_pose": contacts, "compiled": physics.servo.compiled,
            "mj_rtf": mj_rate * dt, "twin_rtf": twin_rate * dt, "profile": hot,
            "sine": sine_tracking(model_name)}


def rows(r: dict) -> list[Row]:
    group = "Twin physics (MuJoCo, no ROS)"
    return [
        Row(group, f"{r['model']}: mj_step(nstep=8) alone at the twin's pose, contacts on / "
            "off", f"{r['mj_step_per_s'] / 1e3:.1f} k steps/s, RTF {r['mj_rtf']:.0f} / "
            f"{r['mj_step_no_contacts_per_s'] / 1e3:.0f} k steps/s ({r['contacts_at_pose']} "
            "contacts)", "report", REPORT, data=r),
        Row(group, f"{r['model']}: full twin cycle (drives set-up + mj_step × 8 + checks), "
            "per step", f"{r['twin_step_per_s'] / 1e3:.1f} k steps/s, RTF {r['twin_rtf']:.0f} "
            + ("(compiled cycle)" if r.get("compiled") else
               "(numpy cycle: libjaka_drives.so not built)"),
            f"report; RTF ≥ {RTF_TARGET:g}", judged(r["twin_rtf"] >= RTF_TARGET),
            note=("" if r["twin_rtf"] >= RTF_TARGET else
                  f"MuJoCo alone, stepped as the twin steps it, runs at RTF {r['mj_rtf']:.0f} "
                  "in the row above (same run): that is the ceiling at a 1 ms physics step. "
                  "The rest of the cycle is paid once per 8 ms: the drives' set-up (in C with "
                  "the compiled cycle) and the Python of the checks, the motion source and the "
                  f"sample (cProfile, own time: {describe(r['profile'])}). With MuJoCo this "
                  "close to the target, a busy machine decides the row."),
            bounds=at_least(r["twin_rtf"], RTF_TARGET, "", "RTF")),
        Row(group, f"{r['model']}: drives' tracking of a {r['sine']['hz']:g} Hz sine of "
            f"{r['sine']['peak_rad_s']:g} rad/s peak, error at each cycle's end",
            f"max {r['sine']['max_rad'] * 1e3:.4f} mrad, RMS {r['sine']['rms_rad'] * 1e3:.4f} "
            "mrad (all joints)", "report", REPORT, data=r["sine"]),
    ]
