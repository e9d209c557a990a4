"""The twin owning time (``sim_time``), zu5:

* **speed**: 60 s of sim time of joint and linear moves, one after the other, through ROS on
  the node at ``real_time_factor:=0``; the wall time it took and the factor reached;
* **determinism**: the same moves (plus a servo stream and a jog left to its watchdog) run
  twice in process on the twin at ``real_time_factor`` 0, once idle and once with both cores
  loaded by two busy processes; the joint samples of every cycle are compared;
* **every timer, stepped**: the determinism test's scenario (test/support/stepped_scenario.py:
  moves, jog and twist watchdogs, a servo gap, a trajectory, a program's ``wait`` and
  ``wait_input``, force zeroing and constant force) on a paused twin its script steps, at
  factor 1 quiet, 1 with both cores loaded and 0 loaded; every field of every sample compared.
"""
from __future__ import annotations

import threading
import time

import numpy as np

from .cpu_load import BusyLoad
from .poses import HOME
from .report import Row, at_most, judged

SIM_SECONDS = 60.0
WALL_TARGET = 15.0
POSES = [[0.5, 1.2, -1.0, 1.9, 1.2, 0.8], [-0.6, 1.8, -1.9, 1.2, 1.9, -0.5], HOME.tolist()]
GROUP = "Simulated time (zu5 twin, real_time_factor 0)"


def _program(joint_move, linear_move, now, seconds: float) -> int:
    """Alternate joint moves and 100 mm linear moves until ``seconds`` of sim time passed;
    returns the number of moves."""
    t0, n, k = now(), 0, 0
    while now() - t0 < seconds:
        assert joint_move(POSES[k % len(POSES)]) == 1
        assert linear_move([0, 0, -100.0 if k % 2 == 0 else 100.0]) == 1
        n, k = n + 2, k + 1
    return n


def speed_through_ros(stack) -> dict:
    """The 60 s program through the node's services; sim time read from the samples."""
    from jaka_msgs.srv import Move
    from sensor_msgs.msg import JointState

    from . import ros_session
    driver = ros_session.start_driver(stack, "bench_sim_time", backend="sim", model="zu5",
                                      sim_time="true", real_time_factor=0)
    stack.callback(ros_session.forget_sim_time)
    calls = ros_session.services(stack, driver)
    joints = ros_session.recorder(stack, driver.name("joint_position"), JointState)
    ros_session.wait_until(joints.latest, 10.0)

    def joint_move(q):
        return calls("joint_move", Move, pose=q, mvvelo=1.5, mvacc=4.0).ret

    def linear_move(dz):
        return calls("linear_move", Move, pose=[0, 0, dz[2], 0, 0, 0], mvvelo=200,
                     mvacc=1000, coord_mode=2).ret

    now = lambda: joints.latest().header.stamp.to_sec()   # noqa: E731
    wall, sim = time.monotonic(), now()
    moves = _program(joint_move, linear_move, now, SIM_SECONDS)
    wall, sim = time.monotonic() - wall, now() - sim
    return {"moves": moves, "sim_s": sim, "wall_s": wall, "factor": sim / wall}


def _in_process_run(loaded: bool, seconds: float) -> tuple[np.ndarray, float]:
    """Joint samples of every cycle of one run (the client holds the clock from the start)."""
    from jaka_driver.driver import RobotDriver
    from jaka_driver.common.models import load_model
    from jaka_driver.common.constants import SERVO_CYCLE as CYCLE
    from jaka_driver.sim import SimBackend

    load = BusyLoad(2).__enter__() if loaded else None
    driver = RobotDriver(SimBackend(load_model("zu5"), sim_time=True, real_time_factor=0))
    clock, seen, done = driver.clock, {}, threading.Event()

    def collect():
        last = -1.0
        while not done.is_set():
            driver.wait_for_sample(last, 0.05)
            for st in driver.states_since(last):
                seen[round(st.stamp / CYCLE)] = st.joint_position.copy()
                last = st.stamp
            clock.consumed(last)

    clock.add_consumer()
    collector = threading.Thread(target=collect, daemon=True)
    collector.start()
    wall = time.monotonic()
    try:
        with clock.hold():
            driver.start()

            def linear_move(dz):
                return driver.linear_move([0, 0, dz[2], 0, 0, 0], 200.0, 1000.0,
                                          coord_mode=2).code

            _program(lambda q: driver.joint_move(q, 1.5, 4.0).code, linear_move, clock.now,
                     seconds)
            assert driver.servo_move_enable(True).ok
            q = driver.state().joint_position.copy()
            for _ in range(125):
                q = q + np.array([0.002, -0.001, 0.0015, 0.0, 0.0, 0.003])
                assert driver.servo_j(q).ok
                clock.sleep(CYCLE)
            assert driver.servo_move_enable(False).ok
            assert driver.jog(0, 0, 0.3).ok
            clock.sleep(3.5)
            end = round(clock.now() / CYCLE)
        wall = time.monotonic() - wall
        deadline = time.monotonic() + 5.0
        while end not in seen and time.monotonic() < deadline:
            time.sleep(0.01)
    finally:
        done.set()
        collector.join(2.0)
        driver.shutdown()
        if load is not None:
            load.stop()
    return np.array([seen[n] for n in range(end + 1)]), wall


def determinism(seconds: float = 20.0) -> dict:
    idle, wall_idle = _in_process_run(False, seconds)
    loaded, wall_loaded = _in_process_run(True, seconds)
    same_length = idle.shape == loaded.shape
    worst = float(np.max(np.abs(idle - loaded))) if same_length else float("inf")
    return {"cycles": [len(idle), len(loaded)], "worst_rad": worst,
            "wall_s": [wall_idle, wall_loaded]}


def stepped_replay() -> dict:
    """The stepped scenario at factor 1 quiet, then 1 and 0 with both cores loaded: the cycles
    compared, the fields that differ, the worst numeric difference, the wall times."""
    from . import ros_session  # noqa: F401 — puts test/ on the path for ``support``
    from support.stepped_scenario import differences, run
    walls, runs = [], []
    for factor, loaded in ((1.0, False), (1.0, True), (0.0, True)):
        wall = time.monotonic()
        runs.append(run(real_time_factor=factor, load=BusyLoad(2) if loaded else None))
        walls.append(time.monotonic() - wall)
    found, worst = [], 0.0
    for other in runs[1:]:
        f, w = differences(runs[0], other)
        found, worst = found + f, max(worst, w)
    return {"cycles": runs[0].cycles, "differences": len(found), "first": found[:5],
            "worst": worst, "wall_s": walls}


def rows(speed: dict | None, same: dict | None, stepped: dict | None = None) -> list[Row]:
    out = []
    if speed is not None:
        out.append(Row(GROUP, f"{SIM_SECONDS:g} s of sim time of joint and linear moves "
                       "through ROS (wall time, factor reached)",
                       f"{speed['wall_s']:.1f} s wall for {speed['sim_s']:.1f} s "
                       f"({speed['moves']} moves): factor {speed['factor']:.1f}",
                       f"≤ {WALL_TARGET:g} s", judged(speed["wall_s"] <= WALL_TARGET),
                       "" if speed["wall_s"] <= WALL_TARGET else
                       "the node publishes every cycle's sample and /clock and the twin waits "
                       "for it; a faster publisher (fewer topics per cycle) would lift the "
                       "factor", data=speed, bounds=at_most(speed["wall_s"], WALL_TARGET, "s")))
    if same is not None:
        ok = same["worst_rad"] <= 1e-9
        out.append(Row(GROUP, "same scenario twice, idle and both cores loaded: worst joint "
                       "difference over every cycle",
                       f"{same['worst_rad']:.1e} rad over {same['cycles'][0]} cycles "
                       f"(wall {same['wall_s'][0]:.1f} s idle, {same['wall_s'][1]:.1f} s "
                       "loaded)", "≤ 1e-9 rad", judged(ok), "" if ok else
                       "a command reached the twin at a different sim time in the two runs",
                       data=same, bounds=at_most(same["worst_rad"], 1e-9, "rad")))
    if stepped is not None:
        ok = stepped["differences"] == 0 and stepped["worst"] == 0.0
        walls = ", ".join(f"{w:.1f}" for w in stepped["wall_s"])
        out.append(Row(GROUP, "stepped twin, every timer (moves, jog and twist watchdogs, servo "
                       "gap, trajectory, program wait/wait_input, zeroing, constant force): "
                       "factor 1 quiet against 1 and 0 with both cores loaded, every field of "
                       "every sample",
                       f"{stepped['differences']} fields differ over {stepped['cycles']} "
                       f"cycles, worst {stepped['worst']:.1e} (wall {walls} s)",
                       "0 differences", judged(ok), "" if ok else
                       f"first: {', '.join(stepped['first'])}", data=stepped))
    return out
