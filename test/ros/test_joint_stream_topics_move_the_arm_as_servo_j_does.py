"""The joint stream on topics follows servo_j exactly: the same targets sent through the servo_j
service, published on ~joint_position_command and on ~joint_command (JointTrajectory, joints
named out of order) give the same samples to 1e-6 rad on the twin (paused and stepped one cycle
per target in sim time, after a reset); a refused message is published on ~command_status
naming the field, the value and the limit, and counted in /diagnostics.

A topic has no answer, so before it steps the twin the test must know that the node has taken
the target: right after each target it publishes, on the same connection, a message the node
refuses (no positions), and steps once that refusal is on ~command_status — a topic's messages
are handled in order, and a refusal changes nothing. (A fixed wait of 50 ms wall was the
alignment before: on a busy machine a target now and then reached the node after the step, one
cycle late, and the samples differed by that target's step — 1.2875 mrad for targets 12, 17,
42 and 47, 2.7094 mrad for 9, 20, 39 and 50.)"""
import numpy as np
import pytest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from support.ros_harness import (START, Recorder, delivers_to_us, start_sim_time_driver, stamp,
                                 wait_until)
from jaka_msgs.srv import ServoMove, ServoMoveEnable
from jaka_driver_msgs.srv import PauseTwin, ResetTwin, StepTwin

pytestmark = pytest.mark.ros

CYCLE = 0.008
NAMES = ["joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"]
#: s of wall time the node is given to handle a message (a busy machine's worst, many times over)
HANDLED = 30.0


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):
    return start_sim_time_driver(request, real_time_factor=1)


@pytest.fixture(scope="module")
def status(sim_driver, rospy_node):
    """~command_status, recorded from the module's start (the node publishing to this process)."""
    recorder = Recorder(sim_driver.name("command_status"), DiagnosticStatus)
    assert wait_until(lambda: delivers_to_us(sim_driver, "command_status"), 10.0)
    yield recorder
    recorder.close()


def refusals(status, topic: str) -> int:
    """How many refusals (WARN) of messages on ``topic`` ~command_status has published."""
    with status._lock:
        return sum(1 for _, m in status.samples
                   if m.name == topic and m.level == DiagnosticStatus.WARN)


def latest_refusal(status) -> DiagnosticStatus:
    """The latest refusal (WARN) on ~command_status (a stream's end is OK: not one)."""
    with status._lock:
        return next((m for _, m in reversed(status.samples)
                     if m.level == DiagnosticStatus.WARN), DiagnosticStatus())


def handled(status, topic: str, publish_refused) -> None:
    """Publish a message the node refuses and wait until its refusal is out: every message
    published on the topic before it has been handled."""
    n = refusals(status, topic) + 1
    publish_refused()
    assert wait_until(lambda: refusals(status, topic) >= n, HANDLED), \
        f"no refusal of {topic} published in {HANDLED} s"


def targets():
    q0 = np.array(START)
    swing = np.array([0.03, -0.02, 0.025, 0.0, 0.02, 0.05])
    return [q0 + swing * np.sin(np.pi * k / 30) for k in range(1, 61)]


def run(call, joints, send):
    """Reset, pause, then per target: send it, step one cycle. The samples (N, 6) of the
    cycles that followed."""
    assert call("sim/reset", ResetTwin, joints=list(START)).ret == 1
    assert call("sim/pause", PauseTwin, pause=True).ret == 1
    try:
        assert call("servo_move_enable", ServoMoveEnable, enable=True).ret == 1
        t0 = call("sim/step", StepTwin, cycles=1).sim_time
        for q in targets():
            send(q)
            reply = call("sim/step", StepTwin, cycles=1)
            assert reply.ret == 1, reply.message
        end = call("sim/step", StepTwin, cycles=10).sim_time
        assert wait_until(lambda: joints.latest() is not None
                          and stamp(joints.latest()) >= end - 1e-6, 10.0)
        with joints._lock:
            by_cycle = {round(stamp(m) / CYCLE): np.array(m.position) for _, m in joints.samples
                        if t0 - 1e-6 < stamp(m) <= end + 1e-6}
        first, last = round(t0 / CYCLE) + 1, round(end / CYCLE)
        assert set(range(first, last + 1)) <= set(by_cycle), "a cycle's sample is missing"
        return np.array([by_cycle[n] for n in range(first, last + 1)])
    finally:
        call("servo_move_enable", ServoMoveEnable, enable=False)
        call("sim/pause", PauseTwin, pause=False)


def test_topic_streams_give_the_samples_of_the_servo_j_service(sim_driver, call, joints, status,
                                                               rospy_node):
    array = rospy_node.Publisher(sim_driver.name("joint_position_command"), Float64MultiArray,
                                 queue_size=10)
    trajectory = rospy_node.Publisher(sim_driver.name("joint_command"), JointTrajectory,
                                      queue_size=10)
    assert wait_until(lambda: array.get_num_connections() and
                      trajectory.get_num_connections(), 5.0)

    def by_service(q):
        assert call("servo_j", ServoMove, pose=list(q), speed=[]).ret == 1

    def by_array(q):
        array.publish(Float64MultiArray(data=list(q)))
        handled(status, array.resolved_name,
                lambda: array.publish(Float64MultiArray(data=[])))

    def by_trajectory(q):
        order = [5, 0, 3, 1, 4, 2]                 # joints named out of order: reordered
        msg = JointTrajectory(joint_names=[NAMES[i] for i in order],
                              points=[JointTrajectoryPoint(positions=[q[i] for i in order])])
        trajectory.publish(msg)
        handled(status, trajectory.resolved_name,
                lambda: trajectory.publish(JointTrajectory(joint_names=NAMES)))

    service = run(call, joints, by_service)
    moved = np.max(np.abs(service - np.array(START)))
    assert moved > 0.02, moved                       # the stream moved the arm
    for send in (by_array, by_trajectory):
        topic = run(call, joints, send)
        assert np.max(np.abs(topic - service)) <= 1e-6, (send.__name__,
                                                          np.max(np.abs(topic - service)))


def test_a_refused_message_is_published_with_field_value_and_limit(sim_driver, call, status,
                                                                   rospy_node):
    diagnostics = Recorder("/diagnostics", DiagnosticArray)
    array = rospy_node.Publisher(sim_driver.name("joint_position_command"), Float64MultiArray,
                                 queue_size=10)
    trajectory = rospy_node.Publisher(sim_driver.name("joint_command"), JointTrajectory,
                                      queue_size=10)
    try:
        assert wait_until(lambda: array.get_num_connections() and
                          trajectory.get_num_connections(), 5.0)
        array.publish(Float64MultiArray(data=[0.0] * 5))
        assert wait_until(lambda: "has 5 values" in latest_refusal(status).message, HANDLED)
        msg = latest_refusal(status)
        assert msg.name.endswith("joint_position_command")
        assert "has 5 values, expected 6" in msg.message, msg.message
        trajectory.publish(JointTrajectory(joint_names=NAMES[:5] + ["wrist"], points=[
            JointTrajectoryPoint(positions=[0.0] * 6)]))
        assert wait_until(lambda: "joint_names" in latest_refusal(status).message, HANDLED)
        # servo mode off: servo_j's own refusal, with its code
        array.publish(Float64MultiArray(data=list(START)))
        assert wait_until(lambda: "servo mode is off" in latest_refusal(status).message,
                          HANDLED)
        values = {kv.key: kv.value for kv in latest_refusal(status).values}
        assert values["ret"] == "-8" and int(values["refused"]) >= 2, values

        def counted():
            latest = diagnostics.latest()
            if latest is None:
                return False
            kv = {v.key: v.value for s in latest.status for v in s.values}
            return any(k.endswith("joint_position_command refused") and int(v) >= 2
                       for k, v in kv.items())
        assert wait_until(counted, HANDLED)      # /diagnostics: 1 Hz
    finally:
        diagnostics.close()
