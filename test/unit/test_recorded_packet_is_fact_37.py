"""The Zu 5s packet recorded on fw 1.5.14, key by key and shape by shape, as docs/protocol.md
("Status packet", the recording's 36 keys) restates it — written here from that list, not from
the emulator: the fixture ``test/data/status_packet_fw1.5.14.json`` and the ``zu5s-1.5.14``
profile's key list must both be it (the emulator's packet is then checked against the fixture
in test_emulator_answers_like_the_transcripts.py)."""
import json

from jaka_driver.emulator.profiles import RECORDED_PACKET_KEYS, profile_named
from support.fake_controller import RECORDED_PACKET, load_status_packet

INT, FLOAT, BOOL, STR = "int", "float", "bool", "str"


def ints(n):
    return [INT] * n


def floats(n):
    return [FLOAT] * n


#: the recording's keys in its order, each with its shape (a number where the recording has
#: one of either kind is FLOAT: 0.0 and 1.0 are written as floats)
FACT_37 = {
    "len": INT, "drag_status": BOOL, "errcode": STR, "errmsg": STR,
    "monitor_data": [INT, INT, FLOAT, FLOAT, FLOAT, [floats(11)] * 6],
    "torqsensor": [[INT, [STR, INT], [FLOAT, ints(3)]], [INT, INT, floats(6), floats(6)]],
    "joint_actual_position": floats(6), "actual_position": floats(6),
    "din": ints(135), "dout": ints(135), "ain": floats(64), "aout": floats(64),
    "tio_din": ints(8), "tio_dout": ints(8), "tio_ain": floats(2),
    "task_state": INT, "homed": ints(9), "task_mode": INT, "interp_state": INT,
    "enabled": BOOL, "paused": BOOL, "rapidrate": FLOAT, "current_tool_id": INT,
    "current_user_id": INT, "on_soft_limit": INT, "emergency_stop": INT,
    "drag_near_limit": ints(6), "funcdi": [ints(2)] * 15, "powered_on": INT, "inpos": BOOL,
    "motion_mode": INT, "curr_tcp_trans_vel": FLOAT, "protective_stop": INT, "point_key": INT,
    "netState": INT, "timestamp": FLOAT,
}


def shape(value):
    if isinstance(value, list):
        return [shape(v) for v in value]
    return {bool: BOOL, int: INT, float: FLOAT, str: STR}[type(value)]


def test_the_fixture_has_the_recorded_keys_in_order_with_their_shapes():
    text = load_status_packet(RECORDED_PACKET)
    packet = json.loads(text)
    assert len(FACT_37) == 36
    assert list(packet) == list(FACT_37)
    assert packet["len"] == len(text.encode())
    for key, expected in FACT_37.items():
        # monitor_data's joint rows: numbers of either kind (the recording writes 0 as 0.0)
        got = shape(packet[key])
        if key == "monitor_data":
            got[5] = [[FLOAT if s == INT else s for s in row] for row in got[5]]
        assert got == expected, key
    assert packet["funcdi"] == [[-1, -1]] * 15


def test_the_recorded_profile_sends_exactly_those_keys():
    assert RECORDED_PACKET_KEYS == tuple(FACT_37)[1:]          # len: the encoder's, first
    assert profile_named("zu5s-1.5.14").packet_keys == RECORDED_PACKET_KEYS
    for absent in ("extio", "tio_key", "position", "joint_position", "relay_io", "instVel"):
        assert absent not in RECORDED_PACKET_KEYS
