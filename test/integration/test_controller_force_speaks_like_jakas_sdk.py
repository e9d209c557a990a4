"""The controller backend's force/torque sensor and force control against the scripted fake
controller (test/fake_controller.py: its torque-sensor replies written from sdk_wire_formats
§5 and §7, not from the emulator), through RobotDriver's door:

- each setting goes out byte for byte as JAKA's SDK writes it (keys sorted, ``"mass":1.50``,
  ``"ftReboundFK":0.250``, its spellings) and is read back with its get, as the SDK reads a
  setting back; a controller that acknowledges but does not take it is refused with 2 after
  the SDK's 1 s; the sensor's on/off, which has no get, is confirmed by the packets;
- the wrench comes from every status packet, with no request per sample; a packet with the
  recorded two wrenches gets ``real`` computed from ``actual`` and the payload it states, as
  the twin defines it; a third wrench is taken as sent;
- identification polls ``get_torq_sensor_identify_staus`` until done, then reads the result;
  a failure the controller reports is answered 2; more than one pose is -2 with nothing sent;
- force control that holds the arm keeps moves out (-10) and stop_move switches it off;
- no sensor configured, or the sensor off as the packets report it: -9, nothing sent.
"""
from __future__ import annotations

import numpy as np
import pytest

from support.fake_controller import fake  # noqa: F401 - the fixture
from support.fake_controller import PROGRAM_STATE_POLL, start_backend
from support.ros_harness import wait_until

from jaka_driver.common.results import Code
from jaka_driver.driver import RobotDriver
from jaka_driver.kinematics import Kinematics


@pytest.fixture
def driver(fake):
    """A RobotDriver on a controller backend whose arm carries a sensor (the fake's)."""
    d = RobotDriver(start_backend(fake, force_sensor=True))
    yield d
    d.shutdown()


@pytest.fixture
def sensor_on(fake, driver):
    assert driver.force.sensor_enable(True).ok
    return driver


def texts_after(fake, count):
    """The requests sent after the first ``count``, as sent (the background program state
    poll's left out: on a busy machine one lands between a setting and its read-back)."""
    with fake.lock:
        return [t for t in fake.texts[count:] if names([t])[0] not in PROGRAM_STATE_POLL]


def sent(fake):
    with fake.lock:
        return len(fake.texts)


def names(texts):
    return [t.split('"cmdName":"')[1].split('"')[0] for t in texts]


#: (door call, what JAKA's SDK sends for it, the get that reads it back or None)
SETTINGS = [
    (lambda f: f.set_sensor_payload(1.5, [0.0, 0.0, 30.0]),
     '{"centroid":[0.0,0.0,30.0],"cmdName":"set_tool_payload","mass":1.50}', "get_tool_payload"),
    (lambda f: f.set_admittance(2, 1, 20.0, 0.25, -10.0, 0),
     '{"axis":2,"cmdName":"set_admit_ctrl_config","ftConstant":-10.0,"ftNnormalTrack":0,'
     '"ftReboundFK":0.250,"ftUser":20.0,"opt":1}', "get_admit_ctrl_config"),
    (lambda f: f.set_tool_drive(0, 1, 30.0, 0.5),
     '{"axis":0,"cmdName":"set_tool_drive_config","opt":1,"rebound":0.5,"rigidity":30.0}',
     "get_tool_drive_config"),
    (lambda f: f.set_compliance_type(True, 1),
     '{"cmdName":"set_compliant_type","compliance_type":1,"sensor_compensation":1}',
     "get_compliant_type"),
    (lambda f: f.set_frame(1), '{"cmdName":"set_ft_ctrl_frame","ftFrame":1}',
     "get_ft_ctrl_frame"),
    (lambda f: f.set_tool_drive_frame(1), '{"cmdName":"set_tool_drive_frame","toolDragFrame":1}',
     "get_tool_drive_frame"),
    (lambda f: f.set_filter(10.0), '{"cmdName":"set_torque_sensor_filter",'
     '"torqueSensorFilter":10.0}', "get_torque_sensor_filter"),
    (lambda f: f.set_soft_limit([50, 50, 80, 5, 5, 4]),
     '{"cmdName":"set_torque_sensor_soft_limit","torqueSensorSoftLimit":{"Fx":50.0,"Fy":50.0,'
     '"Fz":80.0,"Mx":5.0,"My":5.0,"Mz":4.0}}', "get_torque_sensor_soft_limit"),
    (lambda f: f.set_velocity_compliance(2, [0.8, 0.5, 0.2, 0.0]),
     '{"cmdName":"set_vel_compliant_ctrl","compliant_ctrl":[2,0.8,0.5,0.2,0.0]}', None),
    (lambda f: f.set_compliance_condition([0, 0, 30, 0, 0, 0]),
     '{"cmdName":"set_compliance_condition","compliant_condition":[0.0,0.0,30.0,0.0,0.0,'
     '0.0]}', None),
]


def test_each_setting_goes_out_as_jakas_sdk_writes_it_and_is_read_back(fake, driver):
    for call, sdk_text, readback in SETTINGS:
        before = sent(fake)
        result = call(driver.force)
        assert result.ok, result.message
        texts = texts_after(fake, before)
        assert texts[0] == sdk_text
        if readback is None:       # the controller has no get of it
            assert len(texts) == 1 and "accepted" in result.message
        else:
            assert names(texts[1:]) == [readback] and "read back" in result.message
    s = driver.force.settings().value
    assert s.tool_payload.mass == 1.5 and np.allclose(s.tool_payload.centroid, [0, 0, 0.03])
    a = s.admittance[2]
    assert (a.enabled, a.ft_user, a.rebound, a.constant) == (True, 20.0, 0.25, -10.0)  # N/mm
    assert s.tool_drive[0].rebound == 0.5 and (s.compliance_type, s.frame) == (1, 1)
    assert s.filter_hz == 10.0 and list(s.soft_limit) == [50, 50, 80, 5, 5, 4]
    assert s.velocity.level == 2 and list(s.condition) == [0, 0, 30, 0, 0, 0]


def test_a_setting_the_controller_does_not_take_is_refused_with_2(fake, driver):
    fake.sensor.ignored = {"set_torque_sensor_filter", "set_torque_sensor_mode"}
    before = sent(fake)
    refused = driver.force.set_filter(10.0)
    polls = names(texts_after(fake, before)).count("get_torque_sensor_filter")
    assert refused.code == Code.CONTROLLER_REJECTED and "after 1 s" in refused.message, refused
    assert 8 <= polls <= 13                # every 100 ms for 1 s, as JAKA's SDK reads back
    refused = driver.force.sensor_enable(True)
    assert refused.code == Code.CONTROLLER_REJECTED and "status packets" in refused.message
    assert driver.force.settings().value.filter_hz == 0.0 and not driver.state().force


def test_the_wrench_comes_from_every_packet_and_real_is_computed_from_two_vectors(fake, sensor_on):
    driver = sensor_on
    fake.sensor.actual = [1.0, -2.0, 3.0, 0.1, -0.2, 0.3]
    fake.sensor.general = [1.5, -2.5, 3.5, 0.15, -0.25, 0.35]
    assert wait_until(lambda: driver.state().force is not None
                      and driver.state().force.actual[0] == 1.0, 1.0)
    before = sent(fake)
    seen = []
    last = driver.state().stamp
    while len(seen) < 20:               # 20 packets, 8 ms apart
        driver.wait_for_sample(last, 1.0)
        st = driver.state()
        last = st.stamp
        seen.append(st)
    assert texts_after(fake, before) == []          # no request per sample
    st = seen[-1]
    assert list(st.force.actual) == fake.sensor.actual
    assert list(st.force.general) == fake.sensor.general
    assert st.force.status == 1 and st.force.errcode == 0
    # the recorded packet's sensor payload, 0.449 kg at (0, 0, 20) mm, hanging at the flange
    # turned as the packet's joints turn it: real = actual less its weight and moment
    rotation = Kinematics(driver.model).flange_pose(st.joint_position)[:3, :3]
    weight = 0.449 * rotation.T @ np.array([0.0, 0.0, -9.81])
    moment = np.cross([0.0, 0.0, 0.020], weight)
    # (to 1 mN: the backend turns the flange on the controller's own kinematic parameters)
    assert np.allclose(st.force.real, np.array(fake.sensor.actual) - np.r_[weight, moment],
                       atol=1e-3)
    # a controller that sends the third wrench: taken as it is
    fake.sensor.three_vectors = True
    fake.sensor.real = [0.5, 0.5, 0.5, 0.0, 0.0, 0.0]
    assert wait_until(lambda: list(driver.state().force.real) == fake.sensor.real, 1.0)
    result = driver.force.sensor_data(2)      # 2: general
    assert result.ok and list(result.value[0]) == fake.sensor.general


def test_identification_polls_the_status_until_done_then_reads_the_result(fake, sensor_on):
    driver = sensor_on
    fake.sensor.identify_statuses = [0, 1, 1, 1, 0]     # the previous run's 0 first
    fake.sensor.identify_result = {"mass": 1.234, "centroid": [1.0, 2.0, 30.0]}
    end = driver.model.home + np.array([0.0, 0.0, 0.0, 0.5, -0.5, 0.5])
    before = sent(fake)
    progress = []
    result = driver.force.identify_payload(end.tolist(),
                                           feedback=lambda s: progress.append(s.state))
    assert result.ok, result.message
    mass, centroid = result.value
    assert mass == 1.234 and list(centroid) == [1.0, 2.0, 30.0]
    texts = texts_after(fake, before)
    assert texts[0] == ('{"cmdName":"start_torq_sensor_payload_identify","jointPosition":'
                        f'[{",".join(repr(float(v)) for v in np.degrees(end))}]}}')
    polls = names(texts).count("get_torq_sensor_identify_staus")
    assert polls == 5 and names(texts)[-1] == "get_torq_sensor_payload_identify_result"
    assert 1 in progress and driver.force.identification_status().state == 0

    fake.sensor.identify_statuses = [1, 2]
    failed = driver.force.identify_payload(end.tolist())
    assert failed.code == Code.CONTROLLER_REJECTED and "identify_status 2" in failed.message
    assert driver.force.identification_status().state == 2

    before = sent(fake)
    two = driver.force.identify_payload(np.concatenate([end, end]).tolist())
    assert two.code == Code.INVALID_PARAMETER and "one end pose" in two.message
    assert texts_after(fake, before) == []


def test_force_control_keeps_moves_out_and_stop_move_switches_it_off(fake, sensor_on):
    driver = sensor_on
    f = driver.force
    assert f.set_admittance(2, 1, 40.0, 0.0, 10.0).ok and f.set_compliance_type(True, 1).ok
    assert f.enable_admittance(True).ok
    assert fake.sensor.values["stat"]["enable_flag"] == 1
    assert f.settings().value.mode == "constant_force"
    before = sent(fake)
    refused = driver.backend.start_joint_move(driver.model.home, 1.0, 1.0)
    assert refused.code == Code.BUSY and "force control holds the arm" in refused.message
    assert f.zero_sensor().code == Code.BUSY and texts_after(fake, before) == []
    assert driver.stop_move().ok
    assert names(texts_after(fake, before)) == ["disable_force_control", "stop_program"]
    assert f.settings().value.mode == "off" and fake.sensor.values["stat"]["enable_flag"] == 0


def test_the_sensor_off_or_not_configured_is_refused_with_minus_9_and_nothing_sent(fake,
                                                                                    driver):
    f = driver.force
    assert f.set_admittance(2, 1, 40.0, 0.0, 10.0).ok
    before = sent(fake)
    for refused in (f.enable_admittance(True), f.zero_sensor(),
                    f.identify_payload(list(driver.model.home))):
        assert refused.code == Code.WRONG_MODE and "sensor is off" in refused.message, refused
    assert texts_after(fake, before) == []

    plain = RobotDriver(start_backend(fake))            # ~force_sensor not set: none
    try:
        before = sent(fake)
        for refused in (plain.force.sensor_enable(True), plain.force.set_filter(5.0),
                        plain.force.sensor_data(1)):
            assert refused.code == Code.WRONG_MODE and "~force_sensor" in refused.message
        assert plain.state().force is None and texts_after(fake, before) == []
    finally:
        plain.shutdown()
