"""The topic inputs beside the service they stand for, on one node in one run: the servo sine
of :mod:`bench.servo_latency` streamed through the servo_j service, then on
``~joint_position_command`` (Float64MultiArray) and on ``~joint_command`` (JointTrajectory) —
command → observed, each with the floor a causal 8 ms cycle allows and the driver's part above
it, and the node's CPU while each streams — and the velocity input ``~twist_command``: from the
first twist published to the first sample that moves (with the same floor), from the last twist
to rest, and the node's CPU while a teleop streams twists at 125 Hz.

The node's CPU of the four inputs is compared in interleaved windows (:func:`cpu_of_inputs`):
``CPU_ROUNDS`` rounds, each input streamed for ``CPU_STREAM_S`` in every round (the order
turned by one each round) and measured over the middle ``CPU_WINDOW_S``, their sums compared.
Each input costs a few % of a core, and a window of one input after another minutes apart moved
by ±2 points with the host (the servo_j stream measured 4.2 % and 7.8 % in two runs); in
interleaved windows a drift of the host's speed falls on every input alike.
"""
from __future__ import annotations

import time

import numpy as np
import rospy
from geometry_msgs.msg import TwistStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from . import ros_session, servo_latency
from .proc_meter import CpuWindow, MachineWindow
from .report import REPORT, Row, judged
from .stats import fmt, summary
from jaka_driver.common.constants import SERVO_CYCLE

ABOVE_FLOOR_MS = 3.0          # the topic stream's observed p99 target above its floor p99
TWIST_SPEED = 0.05            # m/s
TWIST_TRIALS = 20
TWIST_BURST_S = 0.24          # s of twists per trial
REST_WAIT_S = 0.5             # s after a burst: the watchdog (0.1 s) and the ramp to rest
MOVED_RAD = 1e-6              # a sample this far from the rest pose has moved
CPU_ROUNDS = 4
CPU_STREAM_S = 4.0            # two periods of the sines: each stream ends where it began
CPU_WINDOW_S = 3.0            # measured in the middle of it
TWIST = "~twist_command topic"


def _publisher(driver, leaf: str, msg_type):
    pub = rospy.Publisher(driver.name(leaf), msg_type, queue_size=10, tcp_nodelay=True)
    ros_session.wait_until(lambda: pub.get_num_connections() > 0, 5.0)
    return pub


def array_sender(driver):
    pub = _publisher(driver, "joint_position_command", Float64MultiArray)
    return lambda servo: (lambda q: pub.publish(Float64MultiArray(data=q.tolist())))


def trajectory_sender(driver, names):
    pub = _publisher(driver, "joint_command", JointTrajectory)

    def send(q):
        pub.publish(JointTrajectory(joint_names=names,
                                    points=[JointTrajectoryPoint(positions=q.tolist())]))
    return lambda servo: send


def paced_cycles(seconds: float):
    """Cycle numbers 0, 1, ... for ``seconds``, each yielded at its 8 ms deadline from the
    first (absolute deadlines: a late cycle does not delay the next)."""
    start = time.monotonic()
    for i in range(int(round(seconds / SERVO_CYCLE))):
        delay = start + i * SERVO_CYCLE - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        yield i


def base_twist(vx: float) -> TwistStamped:
    """A twist of ``vx`` m/s along the base frame's x."""
    msg = TwistStamped()
    msg.header.frame_id = "base_link"
    msg.twist.linear.x = vx
    return msg


def twist_trials(driver, joints, trials: int) -> dict:
    """Bursts of twists from rest, alternately +x and -x in the base frame: per trial, the
    first twist's send time, the first sample stamped after it and the first that moved
    (receipt time), and when the arm was at rest after the last twist."""
    pub = _publisher(driver, "twist_command", TwistStamped)
    out = {"sent": [], "arrival_end": [], "moved": [], "last": [], "rest": []}
    for k in range(trials):
        time.sleep(REST_WAIT_S)
        rest = np.array(ros_session.wait_until(joints.latest, 5.0).position)
        direction = 1.0 if k % 2 == 0 else -1.0
        joints.clear()
        sent = last = None
        for _ in paced_cycles(TWIST_BURST_S):
            last = time.time()
            sent = last if sent is None else sent
            pub.publish(base_twist(direction * TWIST_SPEED))
        time.sleep(REST_WAIT_S)
        got = joints.since(sent - 0.1)
        stamps = np.array([m.header.stamp.to_sec() for _, m in got])
        recv = np.array([t for t, _ in got])
        q = np.array([m.position for _, m in got])
        qd = np.array([m.velocity for _, m in got])
        after = np.flatnonzero(stamps >= sent)
        moved = np.flatnonzero((stamps >= sent) & np.any(np.abs(q - rest) > MOVED_RAD, axis=1))
        still = np.flatnonzero((stamps >= last) & np.all(np.abs(qd) < 1e-3, axis=1))
        out["sent"].append(sent)
        out["last"].append(last)
        out["arrival_end"].append(stamps[after[0]] if after.size else np.nan)
        out["moved"].append(recv[moved[0]] if moved.size else np.nan)
        out["rest"].append(stamps[still[0]] if still.size else np.nan)
    return {k: np.array(v) for k, v in out.items()}


def twist_rows(group: str, trials: dict, cpu: dict, service_cpu: dict) -> list[Row]:
    latency = trials["moved"] - trials["sent"]
    wait = trials["arrival_end"] - trials["sent"]
    floor = wait + SERVO_CYCLE
    lat, fl = summary(latency, 1e3), summary(floor, 1e3)
    drv = summary(latency - floor, 1e3)
    stop = summary(trials["rest"] - trials["last"], 1e3)
    missed = int(np.sum(~np.isfinite(latency)))
    stop_ok = stop["max"] is not None and stop["max"] <= 200.0
    return [
        Row(group, "~twist_command: first twist published → first sample that moves, p50 / "
            "p99 / max",
            f"{fmt(lat['p50'])} / {fmt(lat['p99'])} / {fmt(lat['max'])} ms "
            f"({lat['n']} starts from rest, {missed} never moved); the floor a causal 8 ms "
            f"cycle allows p50 / p99 {fmt(fl['p50'], 1)} / {fmt(fl['p99'], 1)} ms, the "
            f"driver's part above it p50 / p99 {fmt(drv['p50'], 1)} / {fmt(drv['p99'], 1)} ms",
            "report", REPORT,
            "The first twist becomes a velocity jog at the end of the cycle it arrived in; "
            "the next cycle's setpoint is the first displaced one, and its sample is the "
            "first that moves (by the ramp's first step, ~0.25 µm at 0.05 m/s and 8 m/s²).",
            data={"latency_ms": lat, "floor_ms": fl, "driver_part_ms": drv}),
        Row(group, "~twist_command: last twist → arm at rest (every joint under 1e-3 rad/s), "
            "p50 / max",
            f"{fmt(stop['p50'])} / {fmt(stop['max'])} ms ({stop['n']} stops)",
            "≤ 200 ms", judged(stop_ok),
            "" if stop_ok else "The watchdog (0.1 s) and the ramp to rest did not end within "
            "0.2 s of the last twist.", data={"stop_ms": stop}),
        Row(group, "node CPU, ~twist_command streamed at 125 Hz",
            f"{cpu['cpu_percent']:.1f} % of one core (servo_j service stream "
            f"{service_cpu['cpu_percent']:.1f} %); machine {cpu['machine_percent']:.0f} % of 1 "
            f"core over {cpu['window_s']:.0f} s", "report", REPORT,
            "Each twist: a velocity jog call (checks; only the first twist of a stream wakes "
            "the watchdog); each cycle in the physics thread: the velocity jog's kinematics "
            "in one C call. Measured in windows interleaved with the servo inputs' (module "
            "docstring).", data=cpu),
    ]


class _Meter:
    """The node's and the machine's CPU summed over the windows of one input."""

    def __init__(self):
        self.node_s = self.machine_s = self.wall_s = 0.0

    def add(self, node: CpuWindow, machine: MachineWindow) -> None:
        self.node_s += node.percent / 100 * node.seconds
        self.machine_s += machine.percent / 100 * node.seconds
        self.wall_s += node.seconds

    def as_dict(self) -> dict:
        return {"cpu_percent": 100 * self.node_s / self.wall_s, "window_s": self.wall_s,
                "machine_percent": 100 * self.machine_s / self.wall_s}


def _measured(driver, meter: _Meter, send_cycle) -> None:
    """``send_cycle(i)`` at 125 Hz for CPU_STREAM_S, the node's CPU taken over the middle
    CPU_WINDOW_S into ``meter``."""
    first = int(round((CPU_STREAM_S - CPU_WINDOW_S) / 2 / SERVO_CYCLE))
    last = first + int(round(CPU_WINDOW_S / SERVO_CYCLE))
    node, machine = CpuWindow(driver.proc.pid), MachineWindow()
    for i in paced_cycles(CPU_STREAM_S):
        if i == first:
            machine.__enter__()
            node.start()
        elif i == last:
            node.stop()
            machine.__exit__(None, None, None)
            meter.add(node, machine)
        send_cycle(i)


def _servo_input(driver, calls, joints, sender):
    """One window of the servo sine through ``sender`` (see servo_latency.sine_stream)."""
    def window(meter: _Meter) -> None:
        center = np.array(ros_session.wait_until(joints.latest, 5.0).position)
        with servo_latency.ServoSession(driver, calls) as servo:
            send = sender(servo)
            _measured(driver, meter, lambda i: send(servo_latency.sine_target(center, i)))
    return window


def _twist_input(driver):
    """One window of a teleop's stream: a 0.5 Hz sine of 0.05 m/s along x at 125 Hz."""
    pub = _publisher(driver, "twist_command", TwistStamped)

    def window(meter: _Meter) -> None:
        _measured(driver, meter, lambda i: pub.publish(base_twist(
            TWIST_SPEED * np.cos(2 * np.pi * 0.5 * i * SERVO_CYCLE))))
        time.sleep(REST_WAIT_S)           # the watchdog and the ramp to rest
    return window


def cpu_of_inputs(inputs: dict) -> dict:
    """label → CPU dict (``cpu_percent`` of one core, ``window_s``, ``machine_percent``) of
    each input (label → ``window(meter)``), over CPU_ROUNDS interleaved rounds."""
    meters = {label: _Meter() for label in inputs}
    labels = list(inputs)
    for r in range(CPU_ROUNDS):
        for label in labels[r % len(labels):] + labels[:r % len(labels)]:
            inputs[label](meters[label])
    return {label: m.as_dict() for label, m in meters.items()}


def run(group: str, driver, calls, *, seconds: float, trials: int, log=print) -> list[Row]:
    rows = []
    joints = ros_session.Recorder(driver.name("joint_position"), JointState)
    try:
        names = list(ros_session.wait_until(joints.latest, 5.0).name)
        senders = {"servo_j service": servo_latency.by_service,
                   "~joint_position_command topic": array_sender(driver),
                   "~joint_command topic": trajectory_sender(driver, names)}
        streams = {}
        for label, sender in senders.items():
            log(f"  servo sine through the {label}, {seconds:g} s")
            streams[label] = servo_latency.sine_stream(driver, calls, joints, seconds, sender)
        log(f"  node CPU of the four inputs: {CPU_ROUNDS} interleaved rounds of "
            f"{CPU_WINDOW_S:g} s each")
        cpu = cpu_of_inputs({**{label: _servo_input(driver, calls, joints, sender)
                                for label, sender in senders.items()},
                             TWIST: _twist_input(driver)})
        service_cpu = cpu["servo_j service"]
        for label, stream in streams.items():
            topic = label != "servo_j service"
            floor = servo_latency.floor_text(servo_latency.observed_latency(stream))[1]["p99"]
            rows.append(servo_latency.observed_row(
                group, f"servo command → observed through the {label}, p50 / p99 / max",
                stream, judge=topic, target_ms=(floor + ABOVE_FLOOR_MS) if topic else None,
                sent_by="publish" if topic else "servo_j call"))
            c = cpu[label]
            cpu_ok = c["cpu_percent"] <= service_cpu["cpu_percent"]
            rows.append(Row(group, f"node CPU while streaming through the {label}",
                            f"{c['cpu_percent']:.1f} % of one core; machine "
                            f"{c['machine_percent']:.0f} % of 1 core over "
                            f"{c['window_s']:.0f} s ({CPU_ROUNDS} windows interleaved with "
                            "the other inputs')",
                            "≤ the servo_j service stream's" if topic else "report",
                            judged(cpu_ok) if topic else REPORT, data=c))
        log(f"  twist: {trials} starts and stops from rest")
        trials_data = twist_trials(driver, joints, trials)
        rows += twist_rows(group, trials_data, cpu[TWIST], service_cpu)
    finally:
        joints.close()
    return rows
