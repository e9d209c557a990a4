"""The torque-sensor and force-control commands as JAKA's SDK 2.1.14 writes and reads them.

Every fixture below is written by hand from what the SDK was measured to send and read (the
team's record of its wire formats, §0 general rules, §3 the tool payload, §5 the sensor and
force control, §7 the status packet's ``torqsensor``), not from this library's encoders: the
request text as the SDK sends it (compact, keys sorted, its spellings "torsenosr", "staus",
"ftNnormalTrack", ints where it sends ints), the reply as a controller writes it. Encoders must
give the same keys, in the same order, with the same JSON types and values; decoders must read
the replies to the values the SDK reads, and refuse what would abort its client."""
import json
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.protocol import encode, parse_reply, parse_status
from jaka_driver.protocol import torque_sensor as t
from jaka_driver.protocol.errors import CommandRejected, InvalidArgument, ProtocolError

Q = [0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0]
RECORDED_PACKET = Path(__file__).resolve().parents[1] / "data" / "status_packet.json"

#: (request as the SDK sends it, the encoder call that must give it)
REQUESTS = [
    ('{"cmdName":"set_torsenosr_brand","sensor_brand":10}', lambda: t.set_torsenosr_brand(10)),
    ('{"cmdName":"get_torsenosr_brand"}', t.get_torsenosr_brand),
    ('{"cmdName":"set_torque_sensor_mode","sensor_mode":1}',
     lambda: t.set_torque_sensor_mode(True)),
    ('{"cmdName":"set_torque_sensor_mode","sensor_mode":0}',
     lambda: t.set_torque_sensor_mode(False)),
    ('{"axis":2,"cmdName":"set_admit_ctrl_config","ftConstant":-10.0,"ftNnormalTrack":0,'
     '"ftReboundFK":0.250,"ftUser":20.0,"opt":1}',
     lambda: t.set_admit_ctrl_config(2, True, 20.0, -10.0, False, 0.25)),
    ('{"cmdName":"get_admit_ctrl_config"}', t.get_admit_ctrl_config),
    ('{"cmdName":"start_torq_sensor_payload_identify","jointPosition":[0.0,90.0,-90.0,90.0,'
     '90.0,0.0]}', lambda: t.start_torq_sensor_payload_identify(Q)),
    ('{"cmdName":"get_torq_sensor_identify_staus"}', t.get_torq_sensor_identify_staus),
    ('{"cmdName":"get_torq_sensor_payload_identify_result"}',
     t.get_torq_sensor_payload_identify_result),
    ('{"cmdName":"enable_admittance_ctrl","enable_flag":1}',
     lambda: t.enable_admittance_ctrl(True)),
    ('{"cmdName":"disable_force_control"}', t.disable_force_control),
    ('{"cmdName":"zero_end_sensor"}', t.zero_end_sensor),
    ('{"axis":0,"cmdName":"set_tool_drive_config","opt":1,"rebound":0.5,"rigidity":30.0}',
     lambda: t.set_tool_drive_config(0, True, 30.0, 0.5)),
    ('{"cmdName":"get_tool_drive_config"}', t.get_tool_drive_config),
    ('{"cmdName":"set_compliant_type","compliance_type":1,"sensor_compensation":1}',
     lambda: t.set_compliant_type(True, 1)),
    ('{"cmdName":"get_compliant_type"}', t.get_compliant_type),
    ('{"cmdName":"set_torque_sensor_comm","ip_addr":"192.168.2.100","port":8080,"type":0}',
     lambda: t.set_torque_sensor_comm(0, "192.168.2.100", 8080)),
    ('{"cmdName":"get_torque_sensor_comm"}', t.get_torque_sensor_comm),
    ('{"cmdName":"set_torque_sensor_filter","torqueSensorFilter":10.0}',
     lambda: t.set_torque_sensor_filter(10.0)),
    ('{"cmdName":"get_torque_sensor_filter"}', t.get_torque_sensor_filter),
    ('{"cmdName":"set_torque_sensor_soft_limit","torqueSensorSoftLimit":{"Fx":50.0,'
     '"Fy":50.0,"Fz":80.0,"Mx":5.0,"My":5.0,"Mz":4.0}}',
     lambda: t.set_torque_sensor_soft_limit([50, 50, 80, 5, 5, 4])),
    ('{"cmdName":"get_torque_sensor_soft_limit"}', t.get_torque_sensor_soft_limit),
    ('{"cmdName":"set_vel_compliant_ctrl","compliant_ctrl":[2,0.8,0.5,0.2,0.0]}',
     lambda: t.set_vel_compliant_ctrl(2, [0.8, 0.5, 0.2, 0.0])),
    ('{"cmdName":"set_compliance_condition","compliant_condition":[0.0,0.0,30.0,0.0,0.0,'
     '0.0]}', lambda: t.set_compliance_condition([0, 0, 30, 0, 0, 0])),
    ('{"cmdName":"set_ft_ctrl_frame","ftFrame":1}', lambda: t.set_ft_ctrl_frame(1)),
    ('{"cmdName":"get_ft_ctrl_frame"}', t.get_ft_ctrl_frame),
    # §5: JAKA's header numbers the readings 1 actual, 2 general, 3 real; sent unchanged
    ('{"cmdName":"get_torque_sensor_data","type":1}', lambda: t.get_torque_sensor_data(1)),
    ('{"cmdName":"get_torque_sensor_data","type":3}', lambda: t.get_torque_sensor_data(3)),
    ('{"cmdName":"get_tool_drive_stat"}', t.get_tool_drive_stat),
    ('{"cmdName":"set_tool_drive_frame","toolDragFrame":0}',
     lambda: t.set_tool_drive_frame(0)),
    ('{"cmdName":"get_tool_drive_frame"}', t.get_tool_drive_frame),
    ('{"cmdName":"set_fusion_drive_sensitivity_level","sensitivity_level":3}',
     lambda: t.set_fusion_drive_sensitivity_level(3)),
    ('{"cmdName":"set_motion_limit_warning_range","range_level":2}',
     lambda: t.set_motion_limit_warning_range(2)),
    ('{"angular_speed_limit":30.0,"cmdName":"set_compliant_speed_limit","speed_limit":100.0}',
     lambda: t.set_compliant_speed_limit(100, 30)),
    ('{"cmdName":"set_torque_ref_point","ref_point":1}', lambda: t.set_torque_ref_point(1)),
    ('{"cmdName":"set_end_sensor_sensitivity_threshold","threshold_percent":[10.0,10.0,10.0,'
     '20.0,20.0,20.0]}', lambda: t.set_end_sensor_sensitivity_threshold([10] * 3 + [20] * 3)),
    ('{"centroid":[0.0,0.0,30.0],"cmdName":"set_tool_payload","mass":1.50}',
     lambda: t.set_tool_payload(1.5, [0, 0, 30])),
]


def _types(value):
    """The JSON shape of ``value``: what a strict reader (jsoncpp) tells apart."""
    if isinstance(value, dict):
        return {k: _types(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_types(v) for v in value]
    return "int" if isinstance(value, int) and not isinstance(value, bool) else type(value).__name__


@pytest.mark.parametrize("sdk, call", REQUESTS, ids=[json.loads(r)["cmdName"] + str(i)
                                                     for i, (r, _) in enumerate(REQUESTS)])
def test_each_request_is_the_sdks_keys_order_types_and_values(sdk, call):
    expected = json.loads(sdk)
    ours = json.loads(encode(call()))
    assert list(ours) == list(expected) == sorted(expected)     # sorted, as jsoncpp writes
    assert _types(ours) == _types(expected)
    assert ours.keys() == expected.keys()
    for key in expected:
        assert np.allclose(ours[key], expected[key]) if not isinstance(expected[key], (str, dict)) \
            else ours[key] == expected[key], key


@pytest.mark.parametrize("sdk, call", [
    ('{"axis":2,"cmdName":"set_admit_ctrl_config","ftConstant":-10.0,"ftNnormalTrack":0,'
     '"ftReboundFK":0.250,"ftUser":20.0,"opt":1}',
     lambda: t.set_admit_ctrl_config(2, True, 20.0, -10.0, False, 0.25)),
    ('{"centroid":[0.0,0.0,30.0],"cmdName":"set_tool_payload","mass":1.50}',
     lambda: t.set_tool_payload(1.5, [0, 0, 30])),
    ('{"centroid":[0.0,0.0,30.0],"cmdName":"set_tool_payload","mass":2.00}',
     lambda: t.set_tool_payload(2.0012, [0, 0, 30])),
    ('{"axis":3,"cmdName":"set_admit_ctrl_config","ftConstant":0.0,"ftNnormalTrack":0,'
     '"ftReboundFK":1.235,"ftUser":5.0,"opt":1}',
     lambda: t.set_admit_ctrl_config(3, True, 5.0, 0.0, False, 1.23456)),
], ids=["rebound", "mass", "mass rounded", "rebound rounded"])
def test_the_fixed_decimal_fields_are_written_as_the_sdk_writes_them(sdk, call):
    """mass with 2 decimals, ftReboundFK with 3, byte for byte (the rest: 16 digits, which
    Python's shortest form equals for these values)."""
    assert encode(call()).decode() == sdk


def reply(text):
    return parse_reply(json.loads(text))


def test_the_admittance_table_is_read_row_by_axis():
    r = reply('{"errorCode": "0", "errorMsg": "", "cmdName": "get_admit_ctrl_config", '
              '"admitConfig": [[0, 0.000000, 0.000000, 0.000000, 0], [0, 0.000000, 0.000000, '
              '0.000000, 0], [1, 20.000000, 0.250000, -10.000000, 0], [0, 0.000000, 0.000000, '
              '0.000000, 0], [0, 0.000000, 0.000000, 0.000000, 0], [0, 0.000000, 0.000000, '
              '0.000000, 0]]}')
    rows = t.reply_admit_ctrl_config(r)
    assert len(rows) == 6 and rows[2] == (1, 20.0, 0.25, -10.0, 0)
    assert all(row.opt == 0 for i, row in enumerate(rows) if i != 2)


def test_the_tool_drive_table_is_opt_rigidity_rebound():
    r = reply('{"errorCode": "0", "errorMsg": "", "cmdName": "get_tool_drive_config", '
              '"force_ctrl_config": [[1, 30.000000, 0.500000], [1, 30.000000, 0.500000], '
              '[1, 40.000000, 0.000000], [0, 0.000000, 0.000000], [0, 0.000000, 0.000000], '
              '[0, 0.000000, 0.000000]]}')
    rows = t.reply_tool_drive_config(r)
    assert rows[0] == (1, 30.0, 0.5) and rows[2].rigidity == 40.0 and rows[5].opt == 0


def test_identification_status_and_result():
    assert t.reply_identify_status(reply(
        '{"errorCode": "0", "errorMsg": "", "cmdName": "get_torq_sensor_identify_staus", '
        '"identify_status": 1}')) == 1
    mass, centroid = t.reply_identify_result(reply(
        '{"errorCode": "0", "errorMsg": "", "cmdName": '
        '"get_torq_sensor_payload_identify_result", "mass": 2.013000, "centroid": [0.400000, '
        '-0.200000, 49.600000]}'))
    assert mass == pytest.approx(2.013) and centroid == pytest.approx([0.4, -0.2, 49.6])


def test_one_reading_is_status_errcode_and_six_values():
    data = t.reply_torque_sensor_data(reply(
        '{"errorCode": "0", "errorMsg": "", "cmdName": "get_torque_sensor_data", "status": 1, '
        '"errcode": 0, "data": [0.120000, -0.050000, -10.020000, 0.001000, 0.002000, '
        '0.000000]}'))
    assert (data.status, data.errcode) == (1, 0)
    assert data.data == pytest.approx([0.12, -0.05, -10.02, 0.001, 0.002, 0.0])


def test_the_other_settings_read_back_as_the_sdk_reads_them():
    ok = '{"errorCode": "0", "errorMsg": "", "cmdName": "x", '
    assert t.reply_compliant_type(reply(ok + '"sensor_compensation": 1, '
                                        '"compliance_type": 2}')) == (1, 2)
    assert t.reply_torque_sensor_filter(reply(ok + '"torqueSensorFilter": 10.000000}')) == 10.0
    limit = t.reply_torque_sensor_soft_limit(reply(
        ok + '"torqueSensorSoftLimit": {"Fx": 50.0, "Fy": 50.0, "Fz": 80.0, "Mx": 5.0, '
        '"My": 5.0, "Mz": 4.0}}'))
    assert limit == pytest.approx([50, 50, 80, 5, 5, 4])
    assert t.reply_int(reply(ok + '"ftFrame": 1}'), "ftFrame") == 1
    assert t.reply_int(reply(ok + '"toolDragFrame": 0}'), "toolDragFrame") == 0
    assert t.reply_tool_drive_stat(reply(ok + '"enable_flag": 1, "drive_stat": 0}')) == (1, 0)
    assert t.reply_compliant_speed_limit(reply(ok + '"speed_limit": 100.0, '
                                               '"angular_speed_limit": 30.0}')) == (100.0, 30.0)
    assert t.reply_sensitivity_threshold(reply(ok + '"threshold_percent": [10, 10, 10, 20, '
                                               '20, 20]}')) == pytest.approx([10] * 3 + [20] * 3)
    assert t.reply_torsenosr_brand(reply(ok + '"sensor_brand": 10}')) == 10


def test_comm_type_1_reads_neither_address_nor_port_as_the_sdk():
    ok = '{"errorCode": "0", "errorMsg": "", "cmdName": "get_torque_sensor_comm", '
    assert t.reply_torque_sensor_comm(reply(ok + '"type": 0, "ip_addr": "192.168.2.100", '
                                            '"port": 8080}')) == (0, "192.168.2.100", 8080)
    assert t.reply_torque_sensor_comm(reply(ok + '"type": 1, "ip_addr": 5}')) == (1, "", 0)


def test_what_would_abort_the_sdks_client_is_a_protocol_error_and_a_refusal_is_rejected():
    ok = '{"errorCode": "0", "errorMsg": "", "cmdName": "x", '
    with pytest.raises(ProtocolError):          # asInt on a string throws in the SDK
        t.reply_identify_status(reply(ok + '"identify_status": "1"}'))
    assert t.reply_identify_status(reply(ok + '"identify_status": 1.0}')) == 1   # asInt: double
    with pytest.raises(ProtocolError):          # indexing a scalar as an array
        t.reply_admit_ctrl_config(reply(ok + '"admitConfig": 3}'))
    with pytest.raises(CommandRejected):
        t.reply_torque_sensor_data(reply('{"errorCode": "2", "errorMsg": "no sensor", '
                                         '"cmdName": "get_torque_sensor_data"}'))
    with pytest.raises(InvalidArgument):
        t.set_admit_ctrl_config(6, True, 20, 0, False, 0)     # axis 0..5: nothing sent
    with pytest.raises(InvalidArgument):
        t.set_compliance_condition([0, 0, float("nan"), 0, 0, 0])
    for kind in (0, 4):                         # JAKA's readings are 1–3: no type 0
        with pytest.raises(InvalidArgument, match="1"):
            t.get_torque_sensor_data(kind)


SDK_TORQSENSOR = [[0, ["192.168.2.100", 8080], [2.0, [0.0, 0.0, 50.0]]],
                  [1, 0, [0.1, 0.0, -10.0, 0.0, 0.0, 0.0], [1.3, -0.8, 21.1, 0.04, -0.03, 0.02],
                   [0.1, 0.0, -10.02, 0.0, 0.0, 0.0]]]


def test_the_status_packets_torqsensor_carries_all_three_wrenches():
    packet = json.loads(RECORDED_PACKET.read_text())
    packet["torqsensor"] = SDK_TORQSENSOR
    s = parse_status(packet).torque_sensor
    assert (s.comm_type, s.ip, s.port) == (0, "192.168.2.100", 8080)
    assert s.payload_mass == 2.0 and s.payload_centroid == pytest.approx([0, 0, 50])
    assert (s.status, s.errcode) == (1, 0)
    assert s.actual == pytest.approx(SDK_TORQSENSOR[1][2])
    assert s.general == pytest.approx(SDK_TORQSENSOR[1][3])
    assert s.real == pytest.approx(SDK_TORQSENSOR[1][4])


def test_the_recorded_two_vector_torqsensor_leaves_the_real_wrench_unknown():
    packet = json.loads(RECORDED_PACKET.read_text())
    parsed = parse_status(packet)
    s = parsed.torque_sensor
    assert s.payload_mass == pytest.approx(0.449) and s.status == 0
    assert np.all(s.actual == 0) and np.all(s.general == 0) and np.all(np.isnan(s.real))
    assert "torqsensor" not in parsed.malformed


def test_comm_type_1_skips_the_address_and_a_wrong_shape_is_counted_malformed():
    packet = {"torqsensor": [[1, None, [0.0, [0, 0, 0]]], [0, 4, [0] * 6, [0] * 6, [0] * 6]]}
    s = parse_status(packet)
    assert s.torque_sensor.ip == "" and s.torque_sensor.port == 0
    assert s.torque_sensor.errcode == 4 and s.sensor_errcode == 4
    broken = parse_status({"torqsensor": [[0, ["ip", 1], [0.0, [0, 0, 0]]], [0, 0, [1, 2]]]})
    assert broken.torque_sensor is None and "torqsensor" in broken.malformed
