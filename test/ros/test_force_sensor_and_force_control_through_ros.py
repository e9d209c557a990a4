"""The force/torque sensor and force control through ROS, on one node: the zu5 twin with a
sensor (``_force_sensor:=true``) over the table of config/scenes/table.yaml.

Every service, the identification action and the topics are there; the latched state tells
what the sensor is and does; ``~wrench`` carries every sample the state topics carry (the
same stamps) in the sensor frame ``flange``, zeroing takes the offset out, a 2 kg payload
reads its weight; the identification action reports progress and finds the payload; constant
force through the services presses 10 N on the table; refusals come back with their reason."""
import time

import actionlib
import numpy as np
import pytest
import rosservice
from geometry_msgs.msg import Wrench, WrenchStamped
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool, Trigger

from jaka_driver.common.models import repo_root
from jaka_driver_msgs.msg import (ForceControlState, IdentifySensorPayloadAction,
                                  IdentifySensorPayloadGoal)
from jaka_driver_msgs.srv import (GetSensorData, GetSensorPayload, SetAdmittance,
                                  SetComplianceType, SetWrench)
from jaka_msgs.srv import SetPayload, ServoMoveEnable
from support.ros_harness import START, Recorder, go_home, start_driver, stamp, wait_until

pytestmark = pytest.mark.ros

FORCE_SERVICES = {
    "zero_ftsensor", "ft_sensor_enable", "set_ft_sensor_payload", "get_ft_sensor_payload",
    "set_ft_sensor_filter", "set_ft_sensor_soft_limit", "get_ft_sensor_data", "set_admittance",
    "set_compliance_type", "set_velocity_compliance", "set_compliance_condition",
    "set_force_control_frame", "enable_admittance", "set_tool_drive", "set_tool_drive_frame",
    "tool_drive_enable", "disable_force_control"}


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):   # conftest's call talks to this node
    return start_driver(request, backend="sim", model="zu5", force_sensor="true",
                        scene=str(repo_root() / "config" / "scenes" / "table.yaml"))


@pytest.fixture(scope="module")
def wrench(sim_driver):
    recorder = Recorder(sim_driver.name("wrench"), WrenchStamped)
    yield recorder
    recorder.close()


@pytest.fixture(scope="module")
def state(sim_driver):
    recorder = Recorder(sim_driver.name("force_control_state"), ForceControlState)
    yield recorder
    recorder.close()


def mean_force(recorder, seconds=0.3):
    """The force (N) averaged over the messages received in the next ``seconds``."""
    t0 = time.time()                    # the recorder's receipt times are time.time()
    time.sleep(seconds)
    msgs = [m for _, m in recorder.since(t0)]
    assert msgs, "no wrench"
    return np.mean([[m.wrench.force.x, m.wrench.force.y, m.wrench.force.z] for m in msgs],
                   axis=0)


def latest_state(recorder, predicate, timeout=3.0):
    msg = wait_until(lambda: (m := recorder.latest()) is not None and predicate(m) and m,
                     timeout)
    assert msg, f"force_control_state never matched; last {recorder.latest()}"
    return msg


def test_every_force_service_the_action_and_the_topics_are_served(sim_driver, state):
    served = {n.rsplit("/", 1)[1] for n in rosservice.get_service_list()
              if n.startswith("/jaka_driver/")}
    assert FORCE_SERVICES <= served, FORCE_SERVICES - served
    assert sim_driver.name("sim/push_tool") in rosservice.get_service_list()
    client = actionlib.SimpleActionClient(sim_driver.name("identify_ft_sensor_payload"),
                                          IdentifySensorPayloadAction)
    assert client.wait_for_server(rospy_timeout(5.0))
    s = latest_state(state, lambda m: True)
    assert s.mounted and not s.sensor_on and s.mode == "off" and s.sensor_frame == "flange"
    assert list(s.range) == [200, 200, 200, 10, 10, 10] and len(s.admittance) == 6


def rospy_timeout(seconds):
    import rospy
    return rospy.Duration(seconds)


def test_the_wrench_carries_every_sample_in_the_sensor_frame_and_zeroes(sim_driver, call, wrench,
                                                                      state):
    assert call("ft_sensor_enable", SetBool, data=True).success
    latest_state(state, lambda m: m.sensor_on)
    joints = Recorder(sim_driver.name("joint_position"), JointState)
    try:
        time.sleep(0.5)
        joint_stamps = [stamp(m) for _, m in list(joints.samples)[5:-5]]
        wrench_stamps = {stamp(m) for _, m in list(wrench.samples)}
        assert len(joint_stamps) > 20
        assert all(t in wrench_stamps for t in joint_stamps)      # every sample, same stamp
    finally:
        joints.close()
    assert wrench.latest().header.frame_id == "flange"
    biased = mean_force(wrench)
    assert np.linalg.norm(biased) > 2.0                 # config's bias: 1.2, -0.8, 2.5 N
    reply = call("zero_ftsensor", Trigger)
    assert reply.success, reply.message
    assert np.linalg.norm(mean_force(wrench)) < 0.3
    data = call("get_ft_sensor_data", GetSensorData, type=2)
    assert data.ret == 1 and data.status == 1 and data.wrench.header.frame_id == "flange"
    assert data.wrench.wrench.force.z == pytest.approx(2.5, abs=0.3)     # general: raw


def test_a_2_kg_payload_reads_its_weight_and_identification_finds_it(sim_driver, call, wrench, state):
    assert call("set_payload", SetPayload, tool_num=0, mass=2.0, xc=0, yc=0, zc=50).ret == 1
    time.sleep(0.5)                     # the drives take up the new weight
    force = mean_force(wrench)
    assert force[2] == pytest.approx(19.62, rel=0.02) and np.linalg.norm(force[:2]) < 0.4
    client = actionlib.SimpleActionClient(sim_driver.name("identify_ft_sensor_payload"),
                                          IdentifySensorPayloadAction)
    assert client.wait_for_server(rospy_timeout(5.0))
    feedback = []
    poses = [np.array(START) + d for d in ([0, 0, 0, 0, -0.8, 0], [0, 0, 0, 0.8, 0, 0],
                                           [0, 0, 0, 0, 0.9, 1.2])]
    client.send_goal(IdentifySensorPayloadGoal(joint_positions=np.concatenate(poses).tolist(),
                                               apply=True),
                     feedback_cb=lambda f: feedback.append(f.progress))
    assert client.wait_for_result(rospy_timeout(60.0))
    result = client.get_result()
    assert result.ret == 1, result.message
    assert result.mass == pytest.approx(2.0, rel=0.02)
    assert np.linalg.norm([result.xc, result.yc, result.zc - 50.0]) <= 2.0
    assert feedback and max(feedback) > 0.5
    s = latest_state(state, lambda m: m.payload_mass > 1.0)
    assert s.payload_centroid[2] == pytest.approx(50.0, abs=2.0)
    got = call("get_ft_sensor_payload", GetSensorPayload)
    assert got.ret == 1 and got.mass == pytest.approx(result.mass)
    go_home(call)
    assert call("set_payload", SetPayload, tool_num=0, mass=0, xc=0, yc=0, zc=0).ret == 1


def test_constant_force_through_the_services_presses_10_n_on_the_table(call, sim_driver, state):
    compensated = Recorder(sim_driver.name("wrench_compensated"), WrenchStamped)
    try:
        assert call("zero_ftsensor", Trigger).success
        reply = call("set_admittance", SetAdmittance, axis=2, opt=1, ft_user=40.0,
                     ft_rebound=0.0, ft_constant=10.0, normal_track=0)
        assert reply.ret == 1, reply.message
        assert call("set_compliance_type", SetComplianceType, sensor_compensation=True,
                    compliance_type=1).ret == 1
        reply = call("enable_admittance", SetBool, data=True)
        assert reply.success, reply.message
        latest_state(state, lambda m: m.mode == "constant_force" and m.admittance[2].opt == 1)
        time.sleep(1.5)                         # the twin settles in ~0.3 s (integration test)
        assert mean_force(compensated, 0.5)[2] == pytest.approx(-10.0, abs=0.5)
        assert call("disable_force_control", Trigger).success
        latest_state(state, lambda m: m.mode == "off")
    finally:
        compensated.close()
        go_home(call)


def test_refusals_come_back_with_their_reason(call):
    reply = call("set_admittance", SetAdmittance, axis=2, opt=1, ft_user=500.0, ft_rebound=0,
                 ft_constant=0, normal_track=0)
    assert reply.ret == -2 and "ft_user" in reply.message and "200" in reply.message
    w = Wrench()
    w.force.z = -1.0
    reply = call("set_compliance_condition", SetWrench, wrench=w)
    assert reply.ret == -2 and "condition Fz" in reply.message
    assert call("set_admittance", SetAdmittance, axis=2, opt=1, ft_user=40.0, ft_rebound=0,
                ft_constant=10.0, normal_track=0).ret == 1
    assert call("servo_move_enable", ServoMoveEnable, enable=True).ret == 1
    try:
        reply = call("enable_admittance", SetBool, data=True)
        assert not reply.success and "servo mode" in reply.message, reply.message
    finally:
        assert call("servo_move_enable", ServoMoveEnable, enable=False).ret == 1
