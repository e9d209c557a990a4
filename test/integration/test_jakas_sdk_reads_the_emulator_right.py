"""JAKA's SDK's own calls (test/support/jaka_sdk_model.py: its requests and its strict reading,
from the measured evidence) against the emulator in its default profile (the controller the SDK is
written for): get_robot_status parses every field right (the IO count in element 0,
monitor_data, instVel, torqsensor, the errcode rules); frames come back by id; every setting
the SDK waits on reads back within its 1 s (also on another connection); programs read as an
idle controller until one is loaded (played in
test_jakas_sdk_runs_programs_and_circles_on_the_emulator.py); login reads seven identity
strings and get_dh_param the twin's own chain; the torque sensor's settings round-trip and what needs a sensor is refused;
the recorded fw 1.5.14 profile's packet and the largest profile's still fit the SDK's buffer and
show their IO."""
from __future__ import annotations

import math
import time

import numpy as np
import pytest

from support.jaka_sdk_model import ABS, RC_BAD_ARGUMENT, RC_FAILED, RC_OK, RC_TIMEOUT, JakaSdk
from support.ros_harness import wait_until

from jaka_driver.emulator import Emulator
from jaka_driver.kinematics import Kinematics
from jaka_driver.kinematics.controller_dh import DHParameters, dh_of_model, flange_pose


EMULATOR = dict(start="enabled")


@pytest.fixture
def sdk(emu):
    handle = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    yield handle
    handle.close()


@pytest.fixture
def other(emu):
    """A second SDK handle: another connection, as another program on the same controller."""
    handle = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    yield handle
    handle.close()


def test_get_robot_status_reads_io_with_the_count_in_element_0(emu, sdk):
    assert sdk.set_digital_output(0, 2, True) == RC_OK
    assert sdk.set_analog_output(0, 6, 2.5) == RC_OK
    assert sdk.set_digital_output(1, 7, True) == RC_OK
    for io_type in (4, 5, 6):                 # Modbus, Profinet, EtherNet/IP slaves
        assert sdk.set_digital_output(io_type, 0, True) == RC_OK
        assert sdk.set_analog_output(io_type, 63, 1.25) == RC_OK
    try:
        rc, st = sdk.get_robot_status()
        assert rc == RC_OK
        assert (st.din[0], st.dout[0], st.ain[0], st.aout[0]) == (144, 144, 66, 66)
        assert (st.tio_din[0], st.tio_dout[0], st.tio_ain[0]) == (8, 8, 1)
        assert st.dout[1 + 2] == 1 and st.aout[1 + 6] == 2.5 and st.tio_dout[1 + 7] == 1
        assert sum(st.dout[1:]) == 1 and sum(st.din[1:]) == 0
        for group in ("modbus_slave", "profinet_slave", "eip_slave"):
            io = st.io_groups[group]
            assert io["dout"][0] == 64 and io["dout"][1] == 1 and io["aout"][64] == 1.25
        assert st.extio["din"][0] == 8 and st.extio["aout"][0] == 4   # its extension module
        assert st.tio_key == [0, 0, 0]
    finally:
        for io_type, index in ((0, 2), (1, 7), (4, 0), (5, 0), (6, 0)):
            sdk.set_digital_output(io_type, index, False)
        for io_type, index in ((0, 6), (4, 63), (5, 63), (6, 63)):
            sdk.set_analog_output(io_type, index, 0.0)


def test_get_robot_status_reads_joints_tcp_monitor_data_and_instvel(emu, sdk):
    # the drives hold the arm against gravity once the twin has run a few cycles
    assert wait_until(lambda: abs(emu.backend.state().joint_effort[1]) > 5.0, 5.0)
    _, st = sdk.get_robot_status()
    twin = emu.backend.state()
    assert np.allclose(st.joint_position, emu.controller.commanded_joints(), atol=1e-6)
    tcp = st.cartesiantran_position
    assert np.allclose(tcp[:3], twin.tcp_pose[:3, 3] * 1000, atol=0.05)
    assert (st.powered_on, st.enabled, st.errcode, st.inpos) == (1, True, 0, True)
    assert st.rapidrate == 1.0 and (st.current_tool_id, st.current_user_id) == (0, 0)
    # at rest: the drives hold the arm against gravity (N·m at [9]), on the 48 V bus
    torques = [j.torque for j in st.joints]
    assert np.allclose(torques, emu.backend.state().joint_effort, atol=1.0)
    assert abs(torques[1]) > 5.0 and all(j.voltage == 48.0 for j in st.joints)
    assert all(abs(j.current - j.torque / 10.0) < 1e-9 for j in st.joints)
    # moving: instVel is the joint speed (deg/s)
    q = np.array(st.joint_position)
    assert sdk.joint_move(q + [0.6, 0, 0, 0, 0, 0], ABS, 0.5, 2.0) == RC_OK
    time.sleep(0.8)                         # past the 0.25 s ramp: cruising at 0.5 rad/s
    _, moving = sdk.get_robot_status()
    assert abs(moving.joints[0].velocity - math.degrees(0.5)) < 3.0
    assert not moving.inpos and moving.average_power > 0.0
    assert sdk.wait_inpos(5.0)
    assert sdk.joint_move(q, ABS, 1.0, 4.0) == RC_OK and sdk.wait_inpos(5.0)


def test_get_robot_status_reads_the_torque_sensor_block(emu, sdk):
    _, st = sdk.get_robot_status()
    assert (st.torq_sensor.ip, st.torq_sensor.port) == ("192.168.2.100", 8080)
    assert sdk.set_torq_sensor_tool_payload(0.45, [0.0, 0.0, 20.0]) == RC_OK
    try:
        _, st = sdk.get_robot_status()
        sensor = st.torq_sensor
        assert sensor.payload_mass == pytest.approx(0.45) and sensor.payload_centroid == [0, 0, 20]
        assert (sensor.status, sensor.errcode) == (0, 0) and sensor.act_torque == [0.0] * 6
    finally:
        assert sdk.set_torq_sensor_tool_payload(0.0, [0.0, 0.0, 0.0]) == RC_OK


def test_errcode_and_the_sdks_overrides_for_stops(emu, sdk):
    sdk.call("emulator_protective_stop", reason="test")
    try:
        _, st = sdk.get_robot_status()
        assert st.protective_stop == 1 and st.errcode == 0x0F0034
    finally:
        assert sdk.call("clear_error")[0] == RC_OK
    sdk.call("emulator_emergency_stop", pressed=1)
    try:
        _, st = sdk.get_robot_status()
        assert st.emergency_stop == 1 and st.errcode == 0x309082 and st.powered_on == 0
    finally:
        sdk.call("emulator_emergency_stop", pressed=0)
        assert sdk.power_on() == RC_OK and sdk.enable_robot() == RC_OK
    _, st = sdk.get_robot_status()
    assert st.errcode == 0


def test_frames_are_read_back_by_id(sdk):
    tool = [10.0, 20.0, 30.0, 0.1, 0.2, 0.3]
    user = [300.0, -200.0, 50.0, 0.0, 0.0, 1.0]
    assert sdk.set_tool_data(3, tool, "gripper") == RC_OK
    assert sdk.set_user_frame_data(10, user, "table") == RC_OK
    try:
        rc, got = sdk.get_tool_data(3)
        assert rc == RC_OK and np.allclose(got, tool, atol=1e-6)
        rc, got = sdk.get_user_frame_data(10)
        assert rc == RC_OK and np.allclose(got, user, atol=1e-6)
        assert sdk.get_tool_data(0) == (RC_OK, [0.0] * 6)        # the flange itself
        assert sdk.get_tool_data(4) == (RC_OK, [0.0] * 6)        # never set
        assert sdk.get_tool_data(11)[0] == RC_BAD_ARGUMENT       # the SDK's own check
        assert sdk.set_tool_data(0, tool, "x") == RC_BAD_ARGUMENT
    finally:
        assert sdk.set_tool_data(3, [0.0] * 6, "") == RC_OK
        assert sdk.set_user_frame_data(10, [0.0] * 6, "") == RC_OK


def test_every_setting_the_sdk_waits_on_reads_back_in_time_on_any_connection(emu, sdk, other):
    assert sdk.set_tool_id(3) == RC_OK and other.get_tool_id() == (RC_OK, 3)
    assert sdk.set_user_frame_id(10) == RC_OK and other.get_user_frame_id() == (RC_OK, 10)
    assert sdk.set_tool_id(0) == RC_OK and sdk.set_user_frame_id(0) == RC_OK
    assert sdk.set_rapidrate(0.5) == RC_OK and other.get_rapidrate() == (RC_OK, 0.5)
    assert sdk.set_rapidrate(1.0) == RC_OK
    assert sdk.drag_mode_enable(True) == RC_OK and other.is_in_drag_mode() == (RC_OK, True)
    assert sdk.drag_mode_enable(False) == RC_OK
    assert sdk.set_torq_sensor_tool_payload(0.5, [0, 0, 30]) == RC_OK
    assert other.get_torq_sensor_tool_payload() == (RC_OK, (0.5, [0.0, 0.0, 30.0]))
    assert sdk.set_torq_sensor_tool_payload(0.0, [0, 0, 0]) == RC_OK
    assert sdk.set_torque_sensor_comm(0, "192.168.2.101", 8081) == RC_OK
    assert other.get_torque_sensor_comm() == (RC_OK, (0, "192.168.2.101", 8081))
    # type 1 skips address and port in the get: the SDK's own wait can never see its port
    assert sdk.set_torque_sensor_comm(1, "", 8080) == RC_TIMEOUT
    assert sdk.set_torque_sensor_comm(0, "192.168.2.100", 8080) == RC_OK
    for io_type in (0, 1, 4, 5, 6):
        assert sdk.set_digital_output(io_type, 0, True) == RC_OK
        assert other.get_digital_output(io_type, 0) == (RC_OK, True)
        assert sdk.set_digital_output(io_type, 0, False) == RC_OK
    assert sdk.set_digital_output(3, 3, True) == RC_OK          # relay 4 (of 4)
    assert sdk.set_digital_output(3, 3, False) == RC_OK
    assert sdk.set_payload(1.5, [0, 0, 50]) == RC_OK
    assert other.get_payload() == (RC_OK, (1.5, [0.0, 0.0, 50.0]))
    assert sdk.set_payload(0.0, [0, 0, 0]) == RC_OK


def test_servo_mode_as_the_sdk_enters_and_leaves_it(emu, sdk):
    assert sdk.servo_j([0.0] * 6, ABS) == RC_FAILED             # "-1": not in servo mode
    assert sdk.servo_move_enable(True) == RC_OK
    q = emu.controller.commanded_joints()
    for k in range(1, 11):
        assert sdk.servo_j(q + [0, 0, 0, 0, 0, 0.002 * k], ABS) == RC_OK
        time.sleep(0.008)
    assert sdk.servo_j(q, ABS, step_num=0) == RC_BAD_ARGUMENT   # the SDK's own check
    assert sdk.servo_move_enable(False) == RC_TIMEOUT           # the SDK's own bug
    assert sdk.is_in_servomove() == (RC_OK, False)


def test_programs_read_as_an_idle_controller_until_one_is_loaded(sdk):
    assert sdk.get_program_state() == (RC_OK, 0)
    assert sdk.get_loaded_program() == (RC_OK, "")
    assert sdk.get_current_line() == (RC_OK, 0)
    assert sdk.program_load("pick") == RC_FAILED and '"programName":"pick.jks"' in sdk.sent[-1]
    assert sdk.program_run() == RC_FAILED
    assert sdk.program_pause() == RC_FAILED and sdk.program_resume() == RC_FAILED
    assert sdk.program_abort() == RC_OK                          # stops motion: the queue is 0
    assert sdk.get_user_var() == (RC_OK, [])


def test_login_reads_seven_strings_and_dh_param_is_the_twins_chain(emu, sdk):
    rc, identity = sdk.login_in()
    assert rc == RC_OK and len(identity) == 7 and all(identity.values())
    rc, dh = sdk.get_dh_param()
    assert rc == RC_OK
    params = DHParameters.from_sdk(dh["alpha"], dh["a"], dh["d"], dh["joint_homeoff"])
    own = dh_of_model(emu.model)
    assert np.allclose(params.a, own.a, atol=1e-9) and np.allclose(params.d, own.d, atol=1e-9)
    kin = Kinematics(emu.model)
    for q in ([0.0] * 6, [0.3, 1.2, -1.1, 1.4, 1.6, 0.2]):
        # the parameters reproduce the twin's own flange pose
        assert np.allclose(flange_pose(params, q)[:3, 3], kin.flange_pose(q)[:3, 3], atol=1e-5)


def test_torque_sensor_settings_round_trip_and_what_needs_a_sensor_is_refused(sdk, other):
    settings = [
        ("set_torsenosr_brand", {"sensor_brand": 3}, "get_torsenosr_brand"),
        ("set_torque_sensor_filter", {"torqueSensorFilter": 0.25}, "get_torque_sensor_filter"),
        ("set_torque_sensor_soft_limit", {"torqueSensorSoftLimit": {
            "Fx": 50.0, "Fy": 50.0, "Fz": 80.0, "Mx": 5.0, "My": 5.0, "Mz": 4.0}},
         "get_torque_sensor_soft_limit"),
        ("set_ft_ctrl_frame", {"ftFrame": 1}, "get_ft_ctrl_frame"),
        ("set_tool_drive_frame", {"toolDragFrame": 1}, "get_tool_drive_frame"),
        ("set_fusion_drive_sensitivity_level", {"sensitivity_level": 3},
         "get_fusion_drive_sensitivity_level"),
        ("set_motion_limit_warning_range", {"range_level": 2}, "get_motion_limit_warning_range"),
        ("set_compliant_speed_limit", {"speed_limit": 100.0, "angular_speed_limit": 30.0},
         "get_compliant_speed_limit"),
        ("set_torque_ref_point", {"ref_point": 1}, "get_torque_ref_point"),
        ("set_end_sensor_sensitivity_threshold",
         {"threshold_percent": [10.0, 10.0, 20.0, 5.0, 5.0, 5.0]},
         "get_end_sensor_sensitivity_threshold"),
        ("set_compliant_type", {"sensor_compensation": 0, "compliance_type": 0},
         "get_compliant_type"),
    ]
    for setter, fields, getter in settings:
        assert sdk.call(setter, **fields)[0] == RC_OK, setter
        rc, reply = other.call(getter)
        assert rc == RC_OK and {k: reply[k] for k in fields} == fields, (getter, reply)
    assert sdk.call("set_admit_ctrl_config", axis=2, opt=1, ftUser=10.0, ftConstant=1.0,
                    ftNnormalTrack=0, ftReboundFK=0.25)[0] == RC_OK
    assert other.call("get_admit_ctrl_config")[1]["admitConfig"][2] == [1, 10.0, 0.25, 1.0, 0]
    assert sdk.call("set_tool_drive_config", axis=5, opt=1, rebound=0.5, rigidity=2.0)[0] == RC_OK
    assert other.call("get_tool_drive_config")[1]["force_ctrl_config"][5] == [1, 2.0, 0.5]
    for command, fields in (("set_torque_sensor_mode", {"sensor_mode": 1}),
                            ("enable_admittance_ctrl", {"enable_flag": 1}),
                            ("set_compliant_type", {"sensor_compensation": 1,
                                                    "compliance_type": 1}),
                            ("start_torq_sensor_payload_identify", {"jointPosition": [0] * 6}),
                            ("zero_end_sensor", {}), ("get_torque_sensor_data", {"type": 3})):
        rc, reply = sdk.call(command, **fields)
        assert rc == RC_FAILED and "torque sensor" in reply["errorMsg"], (command, reply)
    for command, fields in (("set_torque_sensor_mode", {"sensor_mode": 0}),
                            ("enable_admittance_ctrl", {"enable_flag": 0}),
                            ("disable_force_control", {})):
        assert sdk.call(command, **fields)[0] == RC_OK, command
    assert other.call("get_tool_drive_stat")[1] == {
        "errorCode": "0", "errorMsg": "", "cmdName": "get_tool_drive_stat", "enable_flag": 0,
        "drive_stat": 0}


@pytest.mark.parametrize("profile, din, ain, tool_ain, extension",
                         [("zu5s-1.5.14", 135, 64, 2, False), ("large-io", 200, 128, 1, True)])
def test_other_profiles_status_fits_the_sdks_buffer_and_shows_their_io(profile, din, ain,
                                                                       tool_ain, extension):
    with Emulator("zu5", command_port=0, status_port=0, profile=profile,
                  start="enabled") as emulator:
        sdk = JakaSdk("127.0.0.1", emulator.command_port, emulator.data_port)
        try:
            # the extension module, where the cabinet has one; the recorded arm has none
            assert (sdk.set_digital_output(2, 7, True) == RC_OK) == extension
            rc, st = sdk.get_robot_status()
            assert rc == RC_OK and (st.din[0], st.ain[0], st.tio_ain[0]) == (din, ain, tool_ain)
            if extension:
                assert st.extio["dout"][0] == 8 and st.extio["dout"][8] == 1
            else:
                assert st.extio is None
            assert st.powered_on == 1 and st.enabled
        finally:
            sdk.close()
