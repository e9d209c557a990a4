"""Command encoding (the SDK's units in: rad, mm + RPY rad, 0-based IO index; wire units, field
names and 1-based IO index out) and reply decoding."""
import json
import math

import numpy as np
import pytest

from jaka_driver.protocol import commands as c
from jaka_driver.protocol import installation, network_loss
from jaka_driver.protocol import programs as programs
from jaka_driver.protocol import recording as rec
from jaka_driver.protocol import servo_filters as filters
from jaka_driver.protocol import torque_sensor as t
from jaka_driver.protocol.errors import (CommandRejected, InvalidArgument, JakaProtocolError,
                                         ProtocolError)
from jaka_driver.protocol.fields import COMMANDS, Cmd, CoordMap, Field, JogMode

Q = [0.1, -0.2, 0.3, -0.4, 0.5, -0.6]          # rad
Q_DEG = list(np.degrees(Q))
POSE = [400.0, -50.0, 300.0, 0.0, 0.0, math.pi / 2]   # mm + RPY rad
POSE_WIRE = [400.0, -50.0, 300.0, 0.0, 0.0, 90.0]     # mm + RPY deg

# every encoder with sample arguments, to check all of them against the field table
ALL_REQUESTS = [
    c.power_on(), c.power_off(), c.enable_robot(), c.disable_robot(), c.get_robot_state(),
    c.emergency_stop_status(), c.protective_stop_status(), c.clear_error(), c.get_data(),
    c.get_version(), c.quit(),
    c.joint_move(Q, 1.0, 2.0), c.moveL(POSE, 100, 500, tol_mm=0.5),
    c.jog(JogMode.CONTINUOUS, CoordMap.JOINT, 2, 0.1), c.jog(JogMode.STOP, CoordMap.BASE, 0),
    c.stop_program(), c.rapid_rate(0.5),
    c.servo_move(True), c.is_in_servomove(), c.servo_j(Q, step_num=2), c.servo_p(POSE, True, 3),
    filters.servo_filter_none(), filters.servo_filter_joint_lpf(0.5),
    c.get_joint_pos(), c.get_tcp_pos(), c.kine_forward(Q), c.kine_inverse(Q, POSE),
    c.set_tool_offsets(1, POSE, "gripper"), c.set_tool_id(1), c.get_curr_tool_id(),
    c.set_user_offsets(2, POSE, "table"), c.set_user_id(2), c.get_curr_user_id(),
    c.set_payload(1.5, [0, 0, 50]), c.get_payload(),
    c.set_clsn_sensitivity(3), c.get_clsn_sensitivity(), c.drag_status(),
    network_loss.set_network_exception_handle(100.0, network_loss.NetworkLossAction.ABORT),
    installation.set_installation_angle(0.5, 1.0), installation.get_installation_angle(),
    c.set_digital_output(0, 3, True), c.set_analog_output(0, 1, 2.5),
    c.get_digital_input(1, 0), c.get_digital_input_status(), c.get_analog_output(0, 1),
    c.get_digital_output(0, 2), c.get_analog_input(0, 0), c.get_motion_state(),
    c.wait_complete(), c.is_on_limit(), c.end_move(POSE, 0.5, 1.0), c.data_request(),
    c.get_drag_status(), c.get_rapid_rate(), c.get_tool_offsets(), c.get_user_offsets(),
    c.torque_control_enable(True), c.get_dh_param(),
    c.moveL(POSE, 100, 500, ori_vel_rad_s=0.5, ori_acc_rad_s2=1.0),
    c.movc(POSE, POSE, 10, 50, 0.5, 1.5, 2),
    programs.load_program("pick"), programs.get_loaded_program(), programs.play_program(),
    programs.pause_program(), programs.resume_program(), programs.get_program_state(),
    programs.get_current_line(), programs.query_user_defined_variable(),
    programs.modify_user_defined_variable(5, 2.5, "abc"),
    filters.servo_filter_joint_nlf(1, 2, 3), filters.servo_filter_joint_mmf(20, 0.2, 0.4, 0.2),
    filters.servo_filter_carte_nlf(100, 500, 5000, 1, 2, 3), filters.servo_speed_foresight(15, 0.03),
    # the torque sensor and force control (test_protocol_torque_sensor_speaks_jakas_sdk.py)
    t.set_torsenosr_brand(10), t.get_torsenosr_brand(), t.set_torque_sensor_mode(True),
    t.zero_end_sensor(), t.set_tool_payload(0.5, [0, 0, 30]), t.get_tool_payload(),
    t.set_torque_sensor_comm(0, "192.168.2.100", 8080), t.get_torque_sensor_comm(),
    t.set_torque_sensor_filter(10.0), t.get_torque_sensor_filter(),
    t.set_torque_sensor_soft_limit([50, 50, 50, 5, 5, 5]), t.get_torque_sensor_soft_limit(),
    t.get_torque_sensor_data(2), t.start_torq_sensor_payload_identify(Q),
    t.get_torq_sensor_identify_staus(), t.get_torq_sensor_payload_identify_result(),
    t.set_admit_ctrl_config(2, True, 20, -10, False, 0.25), t.get_admit_ctrl_config(),
    t.set_tool_drive_config(0, True, 30, 0.5), t.get_tool_drive_config(),
    t.enable_admittance_ctrl(True), t.disable_force_control(), t.set_compliant_type(True, 1),
    t.get_compliant_type(), t.set_vel_compliant_ctrl(1, [0.5, 0.25, 0, 0]),
    t.set_compliance_condition([0, 0, 30, 0, 0, 0]), t.set_ft_ctrl_frame(0),
    t.get_ft_ctrl_frame(), t.get_tool_drive_stat(), t.set_tool_drive_frame(1),
    t.get_tool_drive_frame(), t.set_fusion_drive_sensitivity_level(3),
    t.get_fusion_drive_sensitivity_level(), t.set_motion_limit_warning_range(2),
    t.get_motion_limit_warning_range(), t.set_compliant_speed_limit(100, 30),
    t.get_compliant_speed_limit(), t.set_torque_ref_point(1), t.get_torque_ref_point(),
    t.set_end_sensor_sensitivity_threshold([10] * 6), t.get_end_sensor_sensitivity_threshold(),
    # trajectory recording
    rec.set_traj_config(0.1, 0.2, 25, 100), rec.get_traj_config(),
    rec.set_traj_sample_mode(True, "rec1"), rec.get_traj_sample_status(),
    rec.get_exist_traj_file_name(), rec.rename_traj_file_name("rec1", "rec2"),
    rec.remove_traj_file("rec2"), rec.generate_traj_exe_file("rec2"),
]


def test_every_command_in_the_table_has_an_encoder_and_vice_versa():
    encoded = {r[Field.CMD_NAME] for r in ALL_REQUESTS}
    assert encoded == set(COMMANDS)
    names = {v for k, v in vars(Cmd).items() if not k.startswith("_")}
    # Cmd also spells commands the library does not send (the emulator answers them)
    assert set(COMMANDS) <= names


@pytest.mark.parametrize("request_", ALL_REQUESTS, ids=lambda r: r[Field.CMD_NAME])
def test_encoders_use_only_the_tabled_field_names(request_):
    spec = COMMANDS[request_[Field.CMD_NAME]]
    assert set(request_) - {Field.CMD_NAME} <= set(spec.request)
    assert spec.confidence in ("high", "medium", "low")
    wire = c.encode(request_)
    assert json.loads(wire.decode("utf-8")) == request_
    assert b" " not in wire.replace(b'"gripper"', b"")   # compact


def test_joint_move_goes_out_in_degrees():
    r = c.joint_move(Q, speed_rad_s=math.pi / 2, accel_rad_s2=math.pi, relative=True)
    assert r[Field.JOINT_POSITION] == pytest.approx(Q_DEG)
    assert r[Field.SPEED] == pytest.approx(90.0)
    assert r[Field.ACCEL] == pytest.approx(180.0)
    assert r[Field.REL_FLAG] == 1
    assert c.joint_move(Q, 1, 1)[Field.REL_FLAG] == 0


def test_move_l_goes_out_in_mm_and_rpy_degrees():
    r = c.moveL(POSE, speed_mm_s=100, accel_mm_s2=500)
    assert r[Field.CMD_NAME] == "moveL"
    assert r[Field.CART_POSITION] == pytest.approx(POSE_WIRE)
    assert (r[Field.SPEED], r[Field.ACCEL], r[Field.REL_FLAG]) == (100, 500, 0)
    assert Field.TOL not in r and Field.ORI_VEL not in r


def test_move_l_carries_the_orientation_limits_in_degrees():
    r = c.moveL(POSE, 100, 500, ori_vel_rad_s=math.pi / 4, ori_acc_rad_s2=math.pi)
    assert (r["ori_vel"], r["ori_acc"]) == pytest.approx((45.0, 180.0))
    with pytest.raises(InvalidArgument, match="orientation speed"):
        c.moveL(POSE, 100, 500, ori_vel_rad_s=0.0)


def test_drag_mode_goes_out_as_torque_control_enable():
    assert c.torque_control_enable(True) == {"cmdName": "torque_control_enable", "enable_flag": 1}
    assert c.torque_control_enable(False)["enable_flag"] == 0


def test_servo_commands():
    j = c.servo_j(Q)
    assert j[Field.JOINT_POSITION] == pytest.approx(Q_DEG)
    assert j[Field.REL_FLAG] == 0 and Field.STEP_NUM not in j
    assert c.servo_j(Q, relative=True, step_num=4)[Field.STEP_NUM] == 4
    p = c.servo_p(POSE, relative=True)
    assert p[Field.SERVO_CART_POSITION] == pytest.approx(POSE_WIRE)
    assert "catPosition" in p and p[Field.REL_FLAG] == 1
    assert c.servo_move(True)[Field.REL_FLAG] == 1
    assert c.servo_move(False)[Field.REL_FLAG] == 0


def test_jog_converts_only_angular_axes():
    joint = c.jog(JogMode.INCREMENT, CoordMap.JOINT, 0, jogvel=math.pi / 4, poscmd=-math.pi / 2)
    assert (joint[Field.JOGVEL], joint[Field.POSCMD]) == pytest.approx((45.0, -90.0))
    linear = c.jog(JogMode.CONTINUOUS, CoordMap.BASE, 2, jogvel=-20.0)
    assert (linear[Field.JOGVEL], linear[Field.POSCMD]) == (-20.0, 0.0)
    rotation = c.jog(JogMode.CONTINUOUS, CoordMap.TOOL, 5, jogvel=math.pi)
    assert rotation[Field.JOGVEL] == pytest.approx(180.0)
    stop = c.jog(JogMode.STOP, CoordMap.JOINT, 4)
    assert set(stop) == {Field.CMD_NAME, Field.JOG_MODE, Field.COORD_MAP, Field.JNUM}


def test_frames_payload_io():
    t = c.set_tool_offsets(3, POSE, "gripper")
    assert t[Field.TOOL_OFFSET] == pytest.approx(POSE_WIRE)
    assert (t[Field.ID], t[Field.NAME]) == (3, "gripper")
    assert c.set_user_offsets(2, POSE)[Field.USER_OFFSET] == pytest.approx(POSE_WIRE)
    assert c.set_user_id(2)[Field.USER_FRAME_ID] == 2
    assert c.set_tool_id(np.int64(4))[Field.TOOL_ID] == 4
    assert c.set_payload(1.5, np.array([1, 2, 3])) == {
        Field.CMD_NAME: "set_payload", Field.MASS: 1.5, Field.CENTROID: [1.0, 2.0, 3.0]}
    assert c.set_digital_output(1, 2, 5)[Field.VALUE] == 1
    assert c.set_digital_output(1, 2, 0)[Field.VALUE] == 0
    assert c.set_clsn_sensitivity(0)[Field.SENSITIVITY_VAL] == 0


@pytest.mark.parametrize("make", [
    lambda: c.joint_move(Q[:5], 1, 1),
    lambda: c.joint_move([math.nan] * 6, 1, 1),
    lambda: c.joint_move(Q, 0.0, 1),
    lambda: c.joint_move(Q, 1, -1),
    lambda: c.joint_move("abc", 1, 1),
    lambda: c.moveL(POSE + [0], 10, 10),
    lambda: c.moveL(POSE, math.inf, 10),
    lambda: c.servo_j(Q, step_num=0),
    lambda: c.jog(7, 0, 0),
    lambda: c.jog(1, 0, 6, 1.0),
    lambda: c.set_tool_id(-1),
    lambda: c.set_tool_id(1.5),
    lambda: c.set_clsn_sensitivity(6),
    lambda: c.set_payload(-1, [0, 0, 0]),
    lambda: c.set_payload(1, [0, 0]),
    lambda: c.rapid_rate(1.5),
    lambda: filters.servo_filter_joint_lpf(None),
    lambda: filters.servo_filter_joint_lpf(0),
    lambda: c.encode({"speed": 1}),
    lambda: c.encode({Field.CMD_NAME: "x", "v": object()}),
])
def test_bad_arguments_are_refused_before_anything_is_sent(make):
    with pytest.raises(InvalidArgument) as info:
        make()
    assert isinstance(info.value, ValueError) and isinstance(info.value, JakaProtocolError)


# ---- replies -------------------------------------------------------------------------------

def test_parse_ok_reply():
    r = c.parse_reply({"cmdName": "get_joint_pos", "errorCode": "0", "errorMsg": "",
                       "joint_pos": [90, 0, 0, 0, 0, -90]})
    assert (r.cmd_name, r.ok, r.error_code, r.error_msg) == ("get_joint_pos", True, "0", "")
    assert dict(r.fields) == {"joint_pos": [90, 0, 0, 0, 0, -90]}
    np.testing.assert_allclose(c.reply_joint_pos(r), [math.pi / 2, 0, 0, 0, 0, -math.pi / 2])
    with pytest.raises(TypeError):
        r.fields["x"] = 1   # read-only


def test_parse_error_reply_keeps_the_message():
    r = c.parse_reply({"cmdName": "joint_move", "errorCode": "2",
                       "errorMsg": "robot is not enabled"})
    assert not r.ok and r.error_code == "2" and r.error_msg == "robot is not enabled"
    with pytest.raises(CommandRejected, match="robot is not enabled") as info:
        c.reply_joint_pos(r)
    assert info.value.reply is r


def test_numeric_error_code_and_missing_message():
    r = c.parse_reply({"errorCode": 0})
    assert r.ok and r.error_code == "0" and r.error_msg == "" and r.cmd_name == ""


@pytest.mark.parametrize("obj", [[1, 2], "x", {"cmdName": "power_on"}])
def test_malformed_replies(obj):
    with pytest.raises(ProtocolError):
        c.parse_reply(obj)


def ok(**fields):
    return c.parse_reply({"cmdName": "x", "errorCode": "0", "errorMsg": "", **fields})


def test_typed_accessors():
    np.testing.assert_allclose(c.reply_tcp_pos(ok(tcp_pos=POSE_WIRE)), POSE, atol=1e-12)
    np.testing.assert_allclose(c.reply_kine_forward(ok(cartPosition=POSE_WIRE)), POSE, atol=1e-12)
    np.testing.assert_allclose(c.reply_kine_inverse(ok(jointPosition=Q_DEG)), Q, atol=1e-12)
    assert c.reply_robot_state(ok(power="powered_on", enable="robot_enabled")) == (True, True)
    assert c.reply_robot_state(ok(power=1, enable="0")) == (True, False)
    assert c.reply_robot_state(ok(power="powered_off", enable=0)) == (False, False)
    assert c.reply_flag(ok(emergency_stop=1), Field.EMERGENCY_STOP) is True
    assert c.reply_flag(ok(in_servomove=False), Field.IN_SERVOMOVE) is False
    assert c.reply_value(ok(value="2.5")) == 2.5
    assert c.reply_din_status(ok(din_status=[0, 1, True])) == (0, 1, 1)
    assert c.reply_id(ok(id=3)) == 3
    assert c.reply_clsn_sensitivity(ok(sensitivityLevel=2)) == 2
    assert c.reply_clsn_sensitivity(ok(sensitivityVal=4)) == 4
    mass, centroid = c.reply_payload(ok(mass=1.5, centroid=[0, 0, 50]))
    assert mass == 1.5 and centroid.tolist() == [0, 0, 50]
    assert c.reply_version(ok(version="1.7.2.16")) == "1.7.2.16"


# the SDK's own test of get_dh_param (sdk_wire_formats): rows alpha deg, a mm, d mm, homeoff deg
DH_WIRE = [[0, 90, 0, 0, 90, -90], [0, 0, 360, 303.5, 0, 0], [120.15, 0, 0, 115, 113.5, 107],
           [0, 90, 0, 90, 0, 0]]


def test_dh_param_rows_become_the_sdk_units():
    dh = c.reply_dh_param(ok(dh_param=DH_WIRE))
    np.testing.assert_allclose(dh.alpha, np.radians(DH_WIRE[0]))
    np.testing.assert_allclose(dh.alpha[[1, 5]], [math.pi / 2, -math.pi / 2])
    assert dh.a.tolist() == DH_WIRE[1] and dh.d.tolist() == DH_WIRE[2]
    np.testing.assert_allclose(dh.joint_homeoff, [0, math.pi / 2, 0, math.pi / 2, 0, 0])


@pytest.mark.parametrize("raw", [
    {"alpha": DH_WIRE[0], "a": DH_WIRE[1], "d": DH_WIRE[2], "joint_homeoff": DH_WIRE[3]},
    sum(DH_WIRE, []),                                   # flat
    DH_WIRE[:3],                                        # a row short
    DH_WIRE + [DH_WIRE[0]],                             # a row too many
    [DH_WIRE[0], DH_WIRE[1][:5], DH_WIRE[2], DH_WIRE[3]],
    [["90"] * 6] + DH_WIRE[1:],                         # a string element
    [[True] * 6] + DH_WIRE[1:],
    [[math.inf] * 6] + DH_WIRE[1:],                     # 1e999 on the wire
    None, "dh",
], ids=["object", "flat", "3-rows", "5-rows", "short-row", "string", "bool", "inf", "null",
        "string-table"])
def test_dh_param_of_any_other_shape_is_refused(raw):
    with pytest.raises(ProtocolError, match="dh_param"):
        c.reply_dh_param(ok(dh_param=raw))


def test_frame_tables_are_read_by_id():
    # the SDK's own test: row i = [10i+1, 10i+2, 10i+3, i, 2i, 90]
    rows = [[10 * i + 1, 10 * i + 2, 10 * i + 3, i, 2 * i, 90] for i in range(11)]
    tools = c.reply_tool_offsets(ok(tool_offsets=rows))
    assert len(tools) == 11
    np.testing.assert_allclose(tools[3], [31, 32, 33, 0.05236, 0.10472, 1.5708], atol=1e-4)
    users = c.reply_user_offsets(ok(user_offsets=rows))
    np.testing.assert_allclose(users[10], [101, 102, 103, *np.radians([10, 20, 90])])
    for bad in ([0, 0, 100, 0, 0, 90], {"1": rows[1]}, [rows[0], rows[1][:5]], []):
        with pytest.raises(ProtocolError, match="tool_offsets"):
            c.reply_tool_offsets(ok(tool_offsets=bad))
    with pytest.raises(ProtocolError, match="tool_offsets"):
        c.reply_tool_offsets(ok(user_offsets=rows))   # the other table


def test_identity_strings_of_get_version():
    ident = c.reply_identity(ok(version="1.5.14_13_X64", robot_id="ZU5S-1", robot_name="JAKA Zu 5",
                                scb_version=172, controller_id=None, other="x"))
    assert ident == {"version": "1.5.14_13_X64", "robot_id": "ZU5S-1", "robot_name": "JAKA Zu 5",
                     "scb_version": "172"}


@pytest.mark.parametrize("reply, read", [
    (ok(), c.reply_joint_pos),
    (ok(joint_pos=[1, 2, 3]), c.reply_joint_pos),
    (ok(tcp_pos="none"), c.reply_tcp_pos),
    (ok(power="maybe", enable=1), c.reply_robot_state),
    (ok(value=None), c.reply_value),
    (ok(id="three"), c.reply_id),
    (ok(value=math.inf), c.reply_value),
    (ok(value=True), c.reply_value),
    (ok(mass=math.nan, centroid=[0, 0, 0]), c.reply_payload),
])
def test_accessors_report_bad_fields(reply, read):
    with pytest.raises(ProtocolError):
        read(reply)


def test_command_name_echo_matching():
    assert c.command_names_match("moveL", "move_l")
    assert c.command_names_match("get_joint_pos", "get_joint_pos")
    assert not c.command_names_match("get_joint_pos", "get_tcp_pos")
