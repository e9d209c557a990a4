"""Servo command → observed through each servo filter beside the unfiltered row, on one node in
one run: the servo sine of :mod:`bench.servo_latency` (every joint, 0.2 rad at 0.5 Hz, 125 Hz
through the servo_j service) streamed once per filter chosen with ``set_servo_filter``, each row
with the floor a causal 8 ms cycle allows that stream and the driver's part above it. A
filter's lag is its row's latency less the unfiltered row's; how much each filter smooths a
stream is its design (docs/interface.md, "set_servo_filter"), not measured here.

The Cartesian non-linear filter (4) acts on ``servo_p`` targets only (JAKA's header): through
servo_j its stream is the unfiltered one, so it has no row.
"""
from __future__ import annotations

import numpy as np
from sensor_msgs.msg import JointState

from jaka_driver_msgs.srv import SetServoFilter

from . import ros_session, servo_latency
from .report import REPORT, Row
from .stats import fmt, summary

#: (label, set_servo_filter fields): the unfiltered stream first, then each joint filter with
#: the parameters docs/interface.md measured it with, and the speed foresight JAKA's ROS node
#: sets at start-up
FILTERS = (
    ("no filter", dict(filter_type=0)),
    ("joint low-pass 2 Hz", dict(filter_type=1, lpf_cutoff_hz=2.0)),
    ("joint non-linear 1 rad/s, 4 rad/s², 40 rad/s³",
     dict(filter_type=2, nlf_max_vr=1.0, nlf_max_ar=4.0, nlf_max_jr=40.0)),
    ("joint multi-order mean 10 cycles, 1 : 2 : 1",
     dict(filter_type=3, mmf_buffer=10, mmf_kp=1.0, mmf_kv=2.0, mmf_ka=1.0)),
    ("speed foresight 10 cycles, kp 0.2", dict(filter_type=5, mmf_buffer=10, mmf_kp=0.2)),
    ("speed foresight 15 cycles, kp 0.03 (JAKA's ROS node's)",
     dict(filter_type=5, mmf_buffer=15, mmf_kp=0.03)),
)


FILTERED_NOTE = ("Through a filter the driver's part above the floor is the filter's lag: the "
                 "setpoint is the filter's output, not the target. A low-pass or a mean also "
                 "flattens the sine's peaks, so the targets near a peak are never reached "
                 "(within the 0.2 s window) and the p99, which counts them as infinitely late, "
                 "reads '—'. ")


def run(group: str, driver, calls, *, seconds: float, log=print) -> list[Row]:
    rows = []
    joints = ros_session.Recorder(driver.name("joint_position"), JointState)
    unfiltered = None
    try:
        ros_session.wait_until(joints.latest, 5.0)
        for label, fields in FILTERS:
            reply = calls("set_servo_filter", SetServoFilter, **fields)
            if reply.ret != 1:
                raise RuntimeError(f"set_servo_filter {label}: {reply.message}")
            log(f"  servo sine through the servo_j service, {label}, {seconds:g} s")
            stream = servo_latency.sine_stream(driver, calls, joints, seconds)
            row = servo_latency.observed_row(
                group, f"servo command → observed, {label}, p50 / p99 / max", stream,
                judge=False)
            latency = servo_latency.observed_latency(stream)["latency_s"]
            p50 = summary(latency[np.isfinite(latency)], 1e3)["p50"]
            if unfiltered is None:
                unfiltered = p50
            else:
                if p50 is not None and unfiltered is not None:
                    row.value += f"; the filter's lag (p50 above the unfiltered row's) " \
                                 f"{fmt(p50 - unfiltered, 1)} ms"
                row.note = FILTERED_NOTE + row.note
            row.target, row.status = "report", REPORT
            rows.append(row)
    finally:
        calls("set_servo_filter", SetServoFilter, filter_type=0)
        joints.close()
    return rows
