"""Program control (§4), servo filters (§6) and the circular move (§9) as JAKA's SDK writes them
on the wire and reads the replies — the fixtures are the requests and replies measured from
JAKA's SDK 2.1.14 (docs/protocol.md, "Programs", "Servo filters", "Circular move"), typed in
here from that record, not produced by our encoders: keys, key order where the SDK sorts them,
value types (an int stays an int, a double a double) and units."""
import json
import math

import pytest

from jaka_driver.protocol import commands as c
from jaka_driver.protocol import programs as p
from jaka_driver.protocol import servo_filters as f
from jaka_driver.protocol.errors import CommandRejected, ProtocolError
from jaka_driver.protocol.replies import parse_reply

# §9: one movc request, as the SDK sent it
MOVC = ('{"accel":50.0,"circle_cnt":0.0,"circle_mode":0,"cmdName":"movc",'
        '"executing_line_id":1,"pos_end":[582.0,114.0,443.0,179.99985,0.0,-90.00021],'
        '"pos_mid":[532.0,164.0,443.0,179.99985,0.0,-90.00021],"relFlag":0,"speed":10.0,'
        '"tol":0.50}')


def wire(request) -> dict:
    """What our encoder puts on the wire, read back (key order kept)."""
    return json.loads(c.encode(request).decode("utf-8"))


def same_json(ours: dict, theirs: dict) -> None:
    """Same keys in the same order, the same types (int / float / str / list), equal values
    (floats to 1e-9 relative: degrees converted from radians)."""
    assert list(ours) == list(theirs)
    for key in theirs:
        a, b = ours[key], theirs[key]
        assert type(a) is type(b), (key, a, b)
        if isinstance(b, list):
            assert a == pytest.approx(b, rel=1e-9), key
            assert [type(x) for x in a] == [type(x) for x in b], key
        elif isinstance(b, float):
            assert a == pytest.approx(b, rel=1e-9), key
        else:
            assert a == b, key


def rad(deg: float) -> float:
    return math.radians(deg)


def test_movc_is_written_as_jakas_sdk_writes_it():
    theirs = json.loads(MOVC)
    ours = wire(c.movc([582.0, 114.0, 443.0, rad(179.99985), 0.0, rad(-90.00021)],
                       [532.0, 164.0, 443.0, rad(179.99985), 0.0, rad(-90.00021)],
                       speed_mm_s=10.0, accel_mm_s2=50.0, tol_mm=0.5, circle_cnt=0,
                       circle_mode=0, executing_line_id=1))
    same_json(ours, theirs)
    assert list(ours) == sorted(ours)                     # the SDK's sorted keys


def test_movc_sends_circle_cnt_as_a_double_and_circle_mode_as_an_int():
    ours = wire(c.movc([0] * 6, [1, 1, 0, 0, 0, 0], 10, 50, circle_cnt=1.5, circle_mode=3,
                       relative=True))
    assert ours["circle_cnt"] == 1.5 and isinstance(ours["circle_cnt"], float)   # 1.50
    assert ours["circle_mode"] == 3 and isinstance(ours["circle_mode"], int)
    assert ours["relFlag"] == 1
    assert b'"circle_cnt":1.5' in c.encode(c.movc([0] * 6, [1, 1, 0, 0, 0, 0], 10, 50,
                                                  circle_cnt=1.5))
    for bad in (dict(circle_mode=4), dict(circle_cnt=-1), dict(speed_mm_s=0)):
        args = dict(speed_mm_s=10, accel_mm_s2=50) | bad
        with pytest.raises(Exception):
            c.movc([0] * 6, [1, 1, 0, 0, 0, 0], **args)


@pytest.mark.parametrize("name, sent", [("x", "x.jks"), ("x.jks", "x.jks.jks"), ("", ".jks"),
                                        ("/abs/path/y", "/abs/path/y.jks")])
def test_load_program_appends_jks_as_jakas_sdk_does(name, sent):
    assert wire(p.load_program(name)) == {"cmdName": "load_program", "programName": sent}


@pytest.mark.parametrize("request_, theirs", [
    (p.get_loaded_program(), {"cmdName": "get_loaded_program"}),
    (p.play_program(), {"cmdName": "play_program"}),
    (p.pause_program(), {"cmdName": "pause_program"}),
    (p.resume_program(), {"cmdName": "resume_program"}),
    (c.stop_program(), {"cmdName": "stop_program"}),
    (p.get_program_state(), {"cmdName": "get_program_state"}),
    (p.get_current_line(), {"cmdName": "get_current_line"}),
    (p.query_user_defined_variable(), {"cmdName": "query_user_defined_variable"}),
    (p.modify_user_defined_variable(5, 2.5, "abc"),
     json.loads('{"alias_new":"abc","cmdName":"modify_user_defined_variable","id_new":5,'
                '"value_new":2.50}')),
])
def test_program_requests_are_jakas_sdks(request_, theirs):
    same_json(wire(request_), theirs)


def reply(**fields):
    return parse_reply({"errorCode": "0", "errorMsg": "", **fields})


def test_program_replies_are_read_as_jakas_sdk_reads_them():
    assert p.reply_loaded_program(reply(programName="pick.jks")) == "pick.jks"
    assert [p.reply_program_state(reply(programState=s))
            for s in ("idle", "running", "paused")] == [0, 1, 2]
    assert p.reply_current_line(reply(current_line=7)) == 7
    listed = p.reply_user_variables(reply(var_list=[{"id": 1, "value": 2.5, "alias": "a"},
                                                    {"id": 5, "value": 0, "alias": "go"}]))
    assert listed == [(1, 2.5, "a"), (5, 0.0, "go")]
    assert len(p.reply_user_variables(reply(var_list=[{"id": i, "value": 0.0, "alias": ""}
                                                      for i in range(150)]))) == 100


@pytest.mark.parametrize("fields, read", [
    ({"programState": 1}, p.reply_program_state),            # a number aborts the SDK
    ({"programState": "RUNNING"}, p.reply_program_state),    # another word: left unchanged
    ({"programName": 3}, p.reply_loaded_program),
    ({"var_list": {"id": 1}}, p.reply_user_variables),       # not an array: SIGSEGV
    ({"var_list": [{"id": "1", "value": 0, "alias": ""}]}, p.reply_user_variables),
    ({"var_list": [{"id": 1, "value": "0", "alias": ""}]}, p.reply_user_variables),
    ({"current_line": "x"}, p.reply_current_line),
])
def test_replies_that_would_break_jakas_sdk_are_protocol_errors(fields, read):
    with pytest.raises(ProtocolError):
        read(reply(**fields))


def test_a_refused_program_command_keeps_the_controllers_message():
    with pytest.raises(CommandRejected, match="no such program"):
        p.reply_loaded_program(parse_reply({"errorCode": "2", "errorMsg": "no such program"}))


@pytest.mark.parametrize("request_, theirs", [
    (f.servo_filter_none(), {"cmdName": "set_servo_move_filter", "filter_type": 0}),
    (f.servo_filter_joint_lpf(0.5),
     {"cmdName": "set_servo_move_filter", "filter_type": 1, "lpf_cf": 0.5}),
    (f.servo_filter_joint_nlf(rad(2), rad(2), rad(4)),
     {"cmdName": "set_servo_move_filter", "filter_type": 2, "nlf_max_vr": 2.0,
      "nlf_max_ar": 2.0, "nlf_max_jr": 4.0}),
    (f.servo_filter_joint_mmf(20, 0.2, 0.4, 0.2),
     {"cmdName": "set_servo_move_filter", "filter_type": 3, "mmf_max_buf": 20, "mmf_kp": 0.2,
      "mmf_kv": 0.4, "mmf_ka": 0.2}),
    (f.servo_filter_carte_nlf(2, 2, 4, rad(2), rad(2), rad(4)),
     {"cmdName": "set_servo_move_filter", "filter_type": 4, "nlf_max_vp": 2.0,
      "nlf_max_ap": 2.0, "nlf_max_jp": 4.0, "nlf_max_vr": 2.0, "nlf_max_ar": 2.0,
      "nlf_max_jr": 4.0}),
    (f.servo_speed_foresight(15, 0.03),
     {"cmdName": "set_servo_move_filter", "filter_type": 5, "mmf_max_buf": 15,
      "mmf_kp": 0.03}),
])
def test_each_filter_type_sends_its_own_keys_in_the_headers_units(request_, theirs):
    same_json(wire(request_), dict(sorted(theirs.items())))     # its keys only, sorted
