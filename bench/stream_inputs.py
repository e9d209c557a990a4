"""The topic inputs beside the service they stand for, on one node in one run: the servo sine
of :mod:`bench.servo_latency` streamed through the servo_j service, then on
``~joint_position_command`` (Float64MultiArray) and on ``~joint_command`` (JointTrajectory) —
command → observed, each with the floor a causal 8 ms cycle allows and the driver's part above
it, and the node's CPU while each streams — and the velocity input ``~twist_command``: from the
first twist published to the first sample that moves (with the same floor), from the last twist
to rest, and the node's CPU while a teleop streams twists at 125 Hz.

The node's CPU of the inputs is compared in interleaved windows, because the host's speed
does not hold still: one input's windows a few seconds apart measured 4.7 and 14.7 % of a core
(the same stream), so windows of one input after another compare the host's seconds, not the
inputs. The three servo inputs share one servo session (:func:`cpu_of_servo_inputs`): the
sender changes every SEGMENT_CYCLES cycles in turn, the node's CPU read at each change on the
kernel's nanosecond clock of the process, so every input meets the same seconds of the host.
The velocity input needs servo mode off, so it is compared with the servo_j service stream in
windows of their own (:func:`cpu_of_inputs`: CPU_ROUNDS rounds, the order swapped each round,
each measured over the middle CPU_WINDOW_S of a CPU_STREAM_S stream).
"""
from __future__ import annotations

import time
import warnings

import numpy as np
import rospy
from geometry_msgs.msg import TwistStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from . import ros_session, servo_latency
from .proc_meter import ProcessCpuClock, machine_busy_seconds
from .report import REPORT, Row, at_most, judged
from .stats import fmt, summary
from jaka_driver.common.constants import SERVO_CYCLE

ABOVE_FLOOR_MS = 3.0          # the topic stream's observed p99 target above its floor p99
TWIST_SPEED = 0.05            # m/s
TWIST_TRIALS = 20
TWIST_BURST_S = 0.24          # s of twists per trial
REST_WAIT_S = 0.5             # s after a burst: the watchdog (0.1 s) and the ramp to rest
MOVED_RAD = 1e-6              # a sample this far from the rest pose has moved
# Twist against the service: S W, W S, S W, ... Many short windows, not a few long ones: in
# records T to V (4 rounds of 3 s) the ratio ranged 1.05–1.31 across runs while the service's
# own windows ranged 4.7–7.2 % of a core; finer turns meet more of the host's swings alike.
CPU_ROUNDS = 12
CPU_STREAM_S = 2.0            # one period of the sines: each stream ends where it began
CPU_WINDOW_S = 1.0            # measured in the middle of it
SEGMENT_CYCLES = 25           # the servo inputs: a sender's turn, 0.2 s
SERVO_CPU_SEGMENTS = 180      # 36 s: 60 turns of each of the three servo inputs
TWIST = "~twist_command topic"


def _publisher(driver, leaf: str, msg_type):
    """A publisher as a servo loop's: each message written to the socket by the sending thread
    (``queue_size=None``). rospy's queued publisher hands every message to a thread of its
    own; on these two cores that thread, the sender and the node's receiving thread made
    three runnable at once, and the node's thread was preempted 0.5-1 times a message
    (bench.thread_meter) — the sender's cost counted as the node's."""
    with warnings.catch_warnings():       # rospy warns of queue_size=None for callbacks' sake
        warnings.simplefilter("ignore")
        pub = rospy.Publisher(driver.name(leaf), msg_type, queue_size=None, tcp_nodelay=True)
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
            "0.2 s of the last twist.", data={"stop_ms": stop},
            bounds=at_most(stop["max"], 200.0, "ms", "max")),
        Row(group, "node CPU, ~twist_command streamed at 125 Hz",
            f"{cpu['cpu_percent']:.1f} % of one core (servo_j service stream "
            f"{service_cpu['cpu_percent']:.1f} % in the windows between); machine "
            f"{cpu['machine_percent']:.0f} % of 1 "
            f"core over {cpu['window_s']:.0f} s", "report", REPORT,
            "Each twist: a velocity jog call (checks; only the first twist of a stream wakes "
            "the watchdog); each cycle in the physics thread: the velocity jog's kinematics "
            "in one C call. Measured in windows interleaved with the servo_j service "
            "stream's (module docstring).",
            data={**cpu, "service_cpu_percent": service_cpu["cpu_percent"]}),
    ]


class _Meter:
    """The node's CPU (its process's nanosecond clock), the machine's and the wall time, summed
    over the windows of one input: :meth:`begin` and :meth:`end` around each window."""

    def __init__(self, clock: ProcessCpuClock):
        self._clock = clock
        self.node_s = self.machine_s = self.wall_s = 0.0
        self.windows = 0
        self._since: tuple | None = None

    def begin(self) -> None:
        self._since = (self._clock(), *machine_busy_seconds())

    def end(self) -> None:
        node0, busy0, t0 = self._since
        busy1, t1 = machine_busy_seconds()
        self.node_s += self._clock() - node0
        self.machine_s += busy1 - busy0
        self.wall_s += t1 - t0
        self.windows += 1
        self._since = None

    def as_dict(self) -> dict:
        return {"cpu_percent": 100 * self.node_s / self.wall_s, "window_s": self.wall_s,
                "machine_percent": 100 * self.machine_s / self.wall_s,
                "windows": self.windows}


def _measured(meter: _Meter, send_cycle) -> None:
    """``send_cycle(i)`` at 125 Hz for CPU_STREAM_S, the node's CPU taken over the middle
    CPU_WINDOW_S into ``meter``."""
    first = int(round((CPU_STREAM_S - CPU_WINDOW_S) / 2 / SERVO_CYCLE))
    last = first + int(round(CPU_WINDOW_S / SERVO_CYCLE))
    for i in paced_cycles(CPU_STREAM_S):
        if i == first:
            meter.begin()
        elif i == last:
            meter.end()
        send_cycle(i)


def _servo_input(driver, calls, joints, sender):
    """One window of the servo sine through ``sender`` (see servo_latency.sine_stream)."""
    def window(meter: _Meter) -> None:
        center = np.array(ros_session.wait_until(joints.latest, 5.0).position)
        with servo_latency.ServoSession(driver, calls) as servo:
            send = sender(servo)
            _measured(meter, lambda i: send(servo_latency.sine_target(center, i)))
    return window


def _twist_input(driver):
    """One window of a teleop's stream: a 0.5 Hz sine of 0.05 m/s along x at 125 Hz, from rest
    to rest (whole periods of a sine velocity: the arm ends where it began, window after
    window; a cosine's stop at full speed moved it ~5 mm further each time, until the twin's
    floor stopped it)."""
    pub = _publisher(driver, "twist_command", TwistStamped)

    def window(meter: _Meter) -> None:
        _measured(meter, lambda i: pub.publish(base_twist(
            TWIST_SPEED * np.sin(2 * np.pi * 0.5 * i * SERVO_CYCLE))))
        time.sleep(REST_WAIT_S)           # the watchdog and the ramp to rest
    return window


def _input_cpu_note(topic: dict, service: dict) -> str:
    """Why a topic stream's CPU came out above the service stream's."""
    return (f"{topic['cpu_percent'] - service['cpu_percent']:+.2f} points of a core "
            f"({topic['cpu_percent']:.2f} against {service['cpu_percent']:.2f} %). Both "
            "streams make the same call in the node (RobotDriver.servo_j_target / servo_j: "
            "the checks and the target handed on); what differs is rospy's own work, about "
            "5 µs a message less for a topic than for a persistent service call (21.5-23.2 "
            "against 27.4-27.7 µs with handlers that do nothing): 0.06 points of a core at "
            "125 Hz. This measurement's standard error, 36 s of the inputs in turns of 0.2 s, "
            "is 0.06-0.11 points, so the row falls either way (bench/README.md, table Z).")


def cpu_of_inputs(driver, inputs: dict) -> dict:
    """label → CPU dict (``cpu_percent`` of one core, ``window_s``, ``machine_percent``,
    ``windows``) of each input (label → ``window(meter)``) of ``driver``'s node, over
    CPU_ROUNDS interleaved rounds."""
    clock = ProcessCpuClock(driver.proc.pid)
    meters = {label: _Meter(clock) for label in inputs}
    labels = list(inputs)
    for r in range(CPU_ROUNDS):
        for label in labels[r % len(labels):] + labels[:r % len(labels)]:
            inputs[label](meters[label])
    return {label: m.as_dict() for label, m in meters.items()}


def cpu_of_servo_inputs(driver, calls, joints, senders: dict) -> dict:
    """label → CPU dict (as :func:`cpu_of_inputs`) of each servo input (label → sender, as
    :func:`servo_latency.sine_stream` takes them), in one servo session: the sine streamed for
    SERVO_CPU_SEGMENTS turns of SEGMENT_CYCLES cycles, the senders taking turns in order, each
    turn measured without its first cycle (a topic's last message of the turn before is
    handled in it)."""
    clock = ProcessCpuClock(driver.proc.pid)
    labels = list(senders)
    meters = {label: _Meter(clock) for label in labels}
    center = np.array(ros_session.wait_until(joints.latest, 5.0).position)
    cycles = SERVO_CPU_SEGMENTS * SEGMENT_CYCLES + 1     # the last turn's end is read too
    with servo_latency.ServoSession(driver, calls) as servo:
        sends = {label: sender(servo) for label, sender in senders.items()}
        for i in paced_cycles(cycles * SERVO_CYCLE):
            turn, phase = divmod(i, SEGMENT_CYCLES)
            label = labels[turn % len(labels)]
            if phase == 0 and turn > 0:
                meters[labels[(turn - 1) % len(labels)]].end()
            elif phase == 1:
                meters[label].begin()
            sends[label](servo_latency.sine_target(center, i))
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
        log(f"  node CPU of the three servo inputs: turns of {SEGMENT_CYCLES} cycles in one "
            f"servo session, {SERVO_CPU_SEGMENTS * SEGMENT_CYCLES * SERVO_CYCLE:g} s")
        cpu = cpu_of_servo_inputs(driver, calls, joints, senders)
        service_cpu = cpu["servo_j service"]
        log(f"  node CPU of ~twist_command and the servo_j service: {CPU_ROUNDS} rounds of "
            f"{CPU_WINDOW_S:g} s each")
        paired = cpu_of_inputs(driver, {
            "servo_j service": _servo_input(driver, calls, joints, servo_latency.by_service),
            TWIST: _twist_input(driver)})
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
                            f"{c['cpu_percent']:.2f} % of one core; machine "
                            f"{c['machine_percent']:.0f} % of 1 core over "
                            f"{c['window_s']:.0f} s ({c['windows']} turns of 0.2 s taken "
                            "in turn with the other servo inputs in one servo session)",
                            "≤ the servo_j service stream's" if topic else "report",
                            judged(cpu_ok) if topic else REPORT,
                            "" if cpu_ok or not topic else _input_cpu_note(c, service_cpu),
                            data=c,
                            bounds=at_most(c["cpu_percent"] - service_cpu["cpu_percent"], 0.0,
                                           "points", "above the service's") if topic else []))
        log(f"  twist: {trials} starts and stops from rest")
        trials_data = twist_trials(driver, joints, trials)
        rows += twist_rows(group, trials_data, paired[TWIST], paired["servo_j service"])
    finally:
        joints.close()
    return rows
