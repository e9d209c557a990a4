"""``python -m bench`` (``make bench``): every benchmark in one run.

Order: the pure-CPU measurements first, while no node runs (IK against KDL, twin physics);
then, on a private rosmaster, start-up via roslaunch, the node on the zu5 twin (state topics
idle and loaded, servo, CPU, joint_move, linear_move), the twin's cameras beside the state
topics (:mod:`bench.cameras`), the topic inputs beside the servo_j
service (:mod:`bench.stream_inputs`), the servo stream through each servo filter
(:mod:`bench.servo_filters`), simulated time, the force/torque sensor and force control
(:mod:`bench.force`), trajectory recording (:mod:`bench.recording`), the gripper on the tool
connector (:mod:`bench.gripper`), and the node on the controller backend through the emulator;
then the
rows that judge the tails against the floors the same run measured (:mod:`bench.floor_targets`).
Writes ``bench/results/latest.json``, ``latest.md`` and the PNG plots.

A group that fails is reported as "not run" with the reason and the others still run; every
process started is stopped on the way out (``ExitStack``), also on SIGINT / SIGTERM.
``--quick`` shortens every window for a smoke run (its numbers are not the benchmark).
``--only controller`` (names from :data:`GROUPS`, comma-separated) runs those groups alone and
writes to ``bench/results/only-<names>/`` (not committed), so that ``bench/results/latest.md``
only ever comes from a whole run; ``--out`` names another folder.

``--runs N`` runs the selected groups N times, one run after the other (one rosmaster), and
writes one table (:mod:`bench.runs`): each targeted row's judged numbers as min / median / max
over the runs, its margin to the target in the worst run, and pass only if it passed in every
run; into ``bench/results/only-<names>-<N>-runs/`` (``all-<N>-runs`` for every group), each
run's own table into its ``run-<k>/`` as that run ends.
``make bench ARGS="--runs 3 --only sim,streams,controller"`` passes arguments through make
(``make bench RUNS=3 ONLY=sim,streams,controller`` says the same).
"""
from __future__ import annotations

import argparse
import datetime as dt
import signal
import sys
import tempfile
import time
import traceback
from contextlib import ExitStack
from pathlib import Path

from .report import NOT_RUN, Row, not_run, write

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "bench" / "results"
SIM = "Sim backend (zu5 twin) through ROS"
EMU = "Controller backend through the emulator (TCP), report only"
#: the groups ``--only`` may name, in the order a whole run takes them
GROUPS = ("ik", "twin", "startup", "sim", "cameras", "streams", "filters", "sim_time",
          "force", "recording", "gripper", "controller")
#: the groups that need a rosmaster
ROS_GROUPS = ("startup", "sim", "cameras", "streams", "filters", "sim_time", "force", "recording",
              "gripper", "controller")
STREAMS = "Topic inputs beside the servo_j service (zu5 twin through ROS)"
FILTERS = "Servo filters beside the unfiltered stream (zu5 twin through ROS), report only"


class Run:
    """Collects rows, raw data and plots; times and logs the groups."""

    def __init__(self, quick: bool):
        self.quick = quick
        self.rows: list[Row] = []
        self.raw: dict = {}
        self.extra: dict = {}
        self.t0 = time.monotonic()

    def log(self, text: str) -> None:
        print(f"[bench {time.monotonic() - self.t0:6.1f} s] {text}", flush=True)

    def guarded(self, group: str, metric: str, target: str, fn) -> bool:
        """Run ``fn()`` (which appends rows); on an exception add a "not run" row."""
        try:
            fn()
            return True
        except Exception as exc:  # noqa: BLE001 - one broken group must not stop the rest
            traceback.print_exc()
            reason = f"{type(exc).__name__}: {str(exc).strip().splitlines()[0][:300]}" \
                if str(exc).strip() else type(exc).__name__
            self.rows.append(not_run(group, metric, target, reason))
            self.log(f"{group}: not run ({reason})")
            return False


def _ik(run: Run) -> None:
    from . import ik_vs_kdl
    n = 1000 if run.quick else ik_vs_kdl.N_TARGETS
    results = []
    for name in ik_vs_kdl.MODEL_NAMES:
        run.log(f"IK vs KDL: {name}, {n} targets")
        results.append(ik_vs_kdl.run_model(name, n))
    run.rows += ik_vs_kdl.rows(results)
    run.raw["ik"] = results
    calibrated = []
    for name in ik_vs_kdl.CALIBRATED:
        run.log(f"IK vs KDL on a calibrated chain: {name}, {n} targets")
        calibrated.append(ik_vs_kdl.run_model(name, n, calibrated=True))
    run.rows += ik_vs_kdl.rows(calibrated, ik_vs_kdl.CALIBRATED_GROUP)
    run.raw["ik_calibrated"] = calibrated


def _twin(run: Run) -> None:
    from . import twin_physics
    run.log("twin physics")
    result = twin_physics.run(seconds=0.5 if run.quick else 1.5)
    run.rows += twin_physics.rows(result)
    # 1000 steps a second (125 cycles) of the twin, as a share of one core
    run.extra["physics_percent"] = 100.0 * 1000.0 / result["twin_step_per_s"]


def _startup(run: Run) -> None:
    from . import startup
    run.log("start-up: roslaunch → first joint_position")
    run.rows += startup.rows(startup.run(1 if run.quick else startup.RUNS))


def _sim(run: Run) -> None:
    from jaka_driver.common.models import load_model

    from . import joint_move_timing, linear_move_accuracy, node_suite, ros_session, servo_latency
    from sensor_msgs.msg import JointState
    with ExitStack() as stack:
        run.log("sim node: starting")
        driver = ros_session.start_driver(stack, "bench_sim", backend="sim", model="zu5")
        calls = ros_session.services(stack, driver)
        rows, raw = node_suite.run(SIM, driver, calls, judge=True,
                                   topic_s=5 if run.quick else 30,
                                   servo_s=3 if run.quick else 16,
                                   rtt_s=1 if run.quick else servo_latency.RTT_SECONDS,
                                   physics_percent=run.extra.get("physics_percent"),
                                   log=run.log)
        run.rows += rows
        run.raw["sim"] = raw
        model = load_model("zu5")
        joints = ros_session.recorder(stack, driver.name("joint_position"), JointState)
        run.log("joint_move timing")
        run.rows += joint_move_timing.rows(joint_move_timing.run(
            model, calls, joints, 3 if run.quick else joint_move_timing.N_MOVES))
        run.log("linear_move accuracy")
        lines = linear_move_accuracy.run(model, driver, calls,
                                         4 if run.quick else linear_move_accuracy.N_LINES)
        run.rows += linear_move_accuracy.rows(lines)
        run.raw["lines"] = lines["lines"]


def _cameras(run: Run) -> None:
    from . import cameras
    with ExitStack() as stack:
        run.rows += cameras.measure(stack, 3 if run.quick else 30, log=run.log)


def _on_a_twin_node(run: Run, name: str, measure) -> None:
    """``measure(driver, calls)`` on a node of its own on the zu5 twin; its rows are kept."""
    from . import ros_session
    with ExitStack() as stack:
        run.log(f"{name} node: starting")
        driver = ros_session.start_driver(stack, f"bench_{name}", backend="sim", model="zu5")
        run.rows += measure(driver, ros_session.services(stack, driver))


def _streams(run: Run) -> None:
    from . import stream_inputs
    _on_a_twin_node(run, "streams", lambda driver, calls: stream_inputs.run(
        STREAMS, driver, calls, seconds=3 if run.quick else 16,
        trials=4 if run.quick else stream_inputs.TWIST_TRIALS, log=run.log))


def _filters(run: Run) -> None:
    from . import servo_filters
    _on_a_twin_node(run, "filters", lambda driver, calls: servo_filters.run(
        FILTERS, driver, calls, seconds=3 if run.quick else 8, log=run.log))


def _sim_time(run: Run) -> None:
    from . import sim_time
    with ExitStack() as stack:
        run.log("sim time: 60 s of moves through ROS at real_time_factor 0")
        speed = sim_time.speed_through_ros(stack)
    run.log("sim time: determinism, idle and loaded")
    same = sim_time.determinism(5.0 if run.quick else 20.0)
    run.log("sim time: every timer on a stepped twin, quiet and loaded, factors 1 and 0")
    stepped = sim_time.stepped_replay()
    run.rows += sim_time.rows(speed, same, stepped)


def _force(run: Run) -> None:
    from . import force, ros_session
    with ExitStack() as stack:
        run.log("force node: starting (the zu5 twin with its sensor over the table)")
        driver = ros_session.start_driver(stack, "bench_force", backend="sim", model="zu5",
                                          force_sensor="true", scene=force.TABLE)
        calls = ros_session.services(stack, driver)
        run.rows += force.run(driver, calls, seconds=3 if run.quick else 20, log=run.log)


def _recording(run: Run) -> None:
    from . import recording, ros_session
    run.log("recording: a known path on the twin in sim time")
    path = recording.known_path(log=run.log)
    with ExitStack() as stack:
        run.log("recording node: starting (the zu5 twin)")
        driver = ros_session.start_driver(stack, "bench_recording", backend="sim", model="zu5",
                                          programs=stack.enter_context(
                                              tempfile.TemporaryDirectory()))
        calls = ros_session.services(stack, driver)
        cpu = recording.recording_cpu(driver, calls, log=run.log)
    run.rows += recording.rows(path, cpu)


def _gripper(run: Run) -> None:
    from . import gripper
    with ExitStack() as stack:
        run.log("gripper: command → motion and grip-state age on the twin and through the "
                "emulator; node CPU with the gripper")
        run.rows += gripper.measure(stack, 6 if run.quick else 40, 3 if run.quick else 20,
                                    log=run.log)


def _emulator(run: Run, out: Path) -> None:
    from jaka_driver.emulator.process import EmulatorProcess

    from . import node_suite, ros_session, servo_latency
    with ExitStack() as stack:
        run.log("emulator: starting")
        # As the rows were measured before the emulator had controller profiles: a packet
        # every servo cycle and the arm on (as the default profile, fw-1.7.2, does; named
        # here so the rows keep their conditions whatever the default).
        emulator = EmulatorProcess("zu5", log_path=str(out / "emulator.log.tmp"),
                                   period=0.008, start="enabled")
        stack.callback(emulator.stop)
        emulator.start()
        driver = ros_session.start_driver(stack, "bench_controller", backend="controller",
                                          model="zu5", ip="127.0.0.1",
                                          command_port=emulator.command_port,
                                          status_port=emulator.status_port)
        calls = ros_session.services(stack, driver)
        rows, raw = node_suite.run(EMU, driver, calls, judge=False,
                                   topic_s=5 if run.quick else 30,
                                   servo_s=3 if run.quick else 16,
                                   rtt_s=1 if run.quick else servo_latency.RTT_SECONDS,
                                   log=run.log)
        run.rows += rows
        run.raw["controller"] = raw
        run.log("controller backend and the twin: node CPU idle, side by side")
        # a namespace of its own: a second /jaka_driver would make the master end the first
        twin = ros_session.start_driver(stack, "bench_controller_twin", ns="beside",
                                        backend="sim", model="zu5")
        run.rows.append(node_suite.side_by_side_row(
            EMU, node_suite.idle_side_by_side({"controller": driver, "twin": twin},
                                              5 if run.quick else 20)))


def _plots(run: Run, out: Path) -> list[str]:
    from . import linear_move_accuracy, plots
    made = []
    sim, ctl = run.raw.get("sim", {}), run.raw.get("controller", {})
    series = {}
    for label, raw in (("sim", sim), ("controller/emulator", ctl)):
        for cond in ("idle", "both cores loaded"):
            topics = raw.get(f"topics {cond}")
            if topics:
                series[f"{label}, {cond}"] = topics["joint_position"]["recv"]
    made.append(plots.period_histogram(series, out))
    made.append(plots.servo_tracking({"sim": sim.get("servo stream"),
                                      "controller/emulator": ctl.get("servo stream")}, out))
    made.append(plots.linear_deviation(run.raw.get("lines", []), out,
                                       linear_move_accuracy.TARGET_MM))
    made.append(plots.ik_times(run.raw.get("ik", []), out))
    return [str(p) for p in made if p is not None]


def _groups(run: Run, chosen: list[str], out: Path, ros_up: bool) -> None:
    """One run of the ``chosen`` groups, in :data:`GROUPS`' order, its rows into ``run``."""
    if "ik" in chosen:
        run.guarded("IK: ours vs PyKDL ChainIkSolverPos_NR_JL", "IK speed and success",
                    "median ≤ 50 µs; ≥ 3× faster than KDL; success ≥ KDL's", lambda: _ik(run))
    if "twin" in chosen:
        run.guarded("Twin physics (MuJoCo, no ROS)", "twin physics", "report; RTF ≥ 150",
                    lambda: _twin(run))
    if ros_up and "startup" in chosen:
        run.guarded("Start-up", "roslaunch → first joint_position", "≤ 3 s",
                    lambda: _startup(run))
    if ros_up and "sim" in chosen:
        run.guarded(SIM, "state topics, servo, CPU, joint_move, linear_move on the twin",
                    "see the table", lambda: _sim(run))
    if ros_up and "cameras" in chosen:
        from .cameras import GROUP as CAMERAS
        run.guarded(CAMERAS, "render time, frame rate and age, state topics and CPU with "
                    "a camera subscribed beside none", "see the table",
                    lambda: _cameras(run))
    if ros_up and "streams" in chosen:
        run.guarded(STREAMS, "joint stream and twist topics beside the servo_j service",
                    "topic p99 ≤ floor + 3 ms; CPU ≤ the service stream's",
                    lambda: _streams(run))
    if ros_up and "filters" in chosen:
        run.guarded(FILTERS, "servo command → observed per servo filter", "report",
                    lambda: _filters(run))
    if ros_up and "sim_time" in chosen:
        run.guarded("Simulated time (zu5 twin, real_time_factor 0)",
                    "60 s of sim time through ROS; determinism idle vs loaded",
                    "≤ 15 s wall; ≤ 1e-9 rad", lambda: _sim_time(run))
    if ros_up and "force" in chosen:
        from .force import GROUP as FORCE
        run.guarded(FORCE, "wrench sample age, constant-force step, CPU with force "
                    "control on", "see the table", lambda: _force(run))
    if ros_up and "recording" in chosen:
        from .recording import GROUP as RECORDING
        run.guarded(RECORDING, "kept points and replay of a known path; node CPU while "
                    "recording", "see the table", lambda: _recording(run))
    if ros_up and "gripper" in chosen:
        from .gripper import GROUP as GRIPPER
        run.guarded(GRIPPER, "gripper command → fingers start moving, grip-state sample age, "
                    "node CPU with the gripper", "see the table", lambda: _gripper(run))
    if ros_up and "controller" in chosen:
        run.guarded(EMU, "controller backend (emulator): rate / age / servo",
                    "report", lambda: _emulator(run, out))
    if {"sim", "streams", "controller"} & set(chosen):
        from . import floor_targets
        run.rows += floor_targets.rows(run.rows, SIM, STREAMS, EMU)


def default_out(chosen: list[str], runs: int) -> Path:
    """Where a run writes: ``bench/results`` for one run of every group (the table of record
    of a whole run), else ``bench/results/only-<groups>[-<N>-runs]/`` (not committed)."""
    if set(chosen) == set(GROUPS) and runs == 1:
        return OUT
    name = "all" if set(chosen) == set(GROUPS) else f"only-{'-'.join(chosen)}"
    return OUT / (name + (f"-{runs}-runs" if runs > 1 else ""))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="short windows: a smoke run, not the benchmark")
    parser.add_argument("--only", default=",".join(GROUPS),
                        help=f"comma-separated groups to run, of: {', '.join(GROUPS)} "
                             "(default: all)")
    parser.add_argument("--runs", type=int, default=1,
                        help="run the selected groups this many times, one run after the other; "
                             "the report gives each targeted row's min / median / max and its "
                             "margin in the worst run, and a row passes only if it passed in "
                             "every run (default 1)")
    parser.add_argument("--out", default=None, help="folder for the results (default "
                        "bench/results for one run of all groups, else "
                        "bench/results/only-<groups>[-<N>-runs])")
    args = parser.parse_args(argv)
    chosen = [g.strip() for g in args.only.split(",") if g.strip()]
    unknown = sorted(set(chosen) - set(GROUPS))
    if unknown or not chosen:
        parser.error(f"--only: unknown group(s) {', '.join(unknown) or '(none given)'}; "
                     f"expected some of {', '.join(GROUPS)}")
    if args.runs < 1:
        parser.error("--runs: at least 1")
    out = Path(args.out) if args.out else default_out(chosen, args.runs)
    for sig in (signal.SIGTERM, signal.SIGHUP):   # unwind, so that finally blocks run
        signal.signal(sig, lambda signum, _frame: sys.exit(128 + signum))
    t0 = time.monotonic()
    started = dt.datetime.now().astimezone().isoformat(timespec="seconds")
    out.mkdir(parents=True, exist_ok=True)

    from .proc_meter import MachineWindow, OtherPrograms
    others = OtherPrograms().start()
    with MachineWindow() as before:
        time.sleep(1.0)
    if before.percent > 30:
        print(f"[bench] warning: the machine is already {before.percent:.0f} % busy (of one "
              "core) before the benchmarks start; numbers will be disturbed", flush=True)
    done: list[Run] = []
    seconds: list[float] = []   # each run's duration
    with ExitStack() as ros:
        from . import ros_session
        ros_up = False
        for k in range(args.runs):
            run = Run(args.quick)
            run.t0 = t0
            run.extra["machine_percent_before"] = before.percent
            if args.runs > 1:
                run.log(f"run {k + 1} of {args.runs}: {', '.join(chosen)}")
            if k == 0:
                ros_up = any(g in ROS_GROUPS for g in chosen) and run.guarded(
                    "ROS", "rosmaster for the ROS benchmarks", "—",
                    lambda: ros_session.start_ros(ros))
            began = time.monotonic()
            _groups(run, chosen, out, ros_up)
            seconds.append(round(time.monotonic() - began, 1))
            done.append(run)
            if args.runs > 1:   # each run's own table as it ends: an interrupted series keeps it
                _, one = write(run.rows, out / f"run-{k + 1}", ROOT, started, seconds[-1], [],
                               run.extra, quick=args.quick)
                run.log(f"run {k + 1} of {args.runs} took {seconds[-1]:.0f} s: {one}")
    run = done[-1]
    try:
        plots = _plots(run, out)
    except Exception:  # noqa: BLE001 - the table matters more than the pictures
        traceback.print_exc()
        plots = []
    run.extra["other_programs"] = others.stop()
    run.extra["machine_percent_during"] = {
        label: raw.get(f"machine {cond}") for label, raw in
        (("sim", run.raw.get("sim", {})), ("controller", run.raw.get("controller", {})))
        for cond in ("idle",)}
    if args.runs > 1:
        from .runs import combine
        rows = combine([r.rows for r in done])
        run.extra["run_seconds"] = seconds
    else:
        rows = run.rows
    json_path, md_path = write(rows, out, ROOT, started, time.monotonic() - t0, plots,
                               run.extra, quick=args.quick, runs=args.runs)
    failed = sum(r.status == "FAIL" for r in rows)
    missing = sum(r.status == NOT_RUN for r in rows)
    shown = md_path.resolve()
    shown = shown.relative_to(ROOT) if ROOT in shown.parents else shown
    run.log(f"wrote {shown} and {json_path.name}: "
            f"{failed} targets missed, {missing} rows not run")
    print(md_path.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
