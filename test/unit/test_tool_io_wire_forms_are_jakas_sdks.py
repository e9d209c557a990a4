"""The controller backend's tool-connector requests are JAKA's SDK's, byte for byte (the
measured requests: test/support/jaka_sdk_tio.py, docs/protocol.md "Tool connector"), and its
readers take the replies and the status packet's ``tio_rs_signals`` as JAKA's SDK does —
refusing, where the SDK would abort, a field of the wrong type."""
import pytest

from support.jaka_sdk_tio import SDK_REQUESTS

from jaka_driver.protocol import tool_io as wire
from jaka_driver.protocol.commands import encode
from jaka_driver.protocol.errors import CommandRejected, InvalidArgument, ProtocolError
from jaka_driver.protocol.replies import parse_reply
from jaka_driver.protocol.status_packet import parse_status

#: the SDK's function → this library's encoder (get_rs485_signal_info sends get_tio_signals)
ENCODERS = {"set_tio_vout_param": wire.set_tio_vout_param,
            "get_tio_vout_param": wire.get_tio_vout_param,
            "set_tio_pin_mode": lambda t, m: wire.set_tio_pin_mode(t, m),
            "get_tio_pin_mode": wire.get_tio_pin_mode,
            "set_rs485_chn_mode": wire.set_rs485_chn_mode,
            "get_rs485_chn_mode": wire.get_rs485_chn_mode,
            "set_rs485_chn_comm": wire.set_rs485_chn_comm,
            "get_rs485_chn_comm": wire.get_rs485_chn_comm,
            "add_tio_rs_signal": wire.add_tio_rs_signal,
            "del_tio_rs_signal": wire.del_tio_rs_signal,
            "send_tio_rs_command": wire.send_tio_rs_command,
            "get_rs485_signal_info": wire.get_tio_signals}


@pytest.mark.parametrize("call, measured", list(SDK_REQUESTS.items()),
                         ids=[f for f, _ in SDK_REQUESTS])
def test_each_request_is_the_measured_one(call, measured):
    function, args = call
    assert encode(ENCODERS[function](*args)) == measured.encode()


def test_the_sdk_argument_order_of_set_rs485_chn_comm_is_kept():
    # JAKA's ModRtuComm {chn_id, slaveId, baudrate, databit, stopbit, parity}
    assert wire.set_rs485_chn_comm(1, 9, 9600, 7, 2, 69) == {
        "baudrate": 9600, "chn_id": 1, "cmdName": "set_rs485_chn_comm", "databit": 7,
        "parity": 69, "slaveId": 9, "stopbit": 2}


def test_a_value_that_is_no_integer_is_never_sent():
    with pytest.raises(InvalidArgument):
        wire.set_tio_vout_param(1, 0.5)
    with pytest.raises(InvalidArgument):
        wire.send_tio_rs_command(1, [1, "6"])
    with pytest.raises(InvalidArgument):
        wire.add_tio_rs_signal(5, 1, 3, 258, 5)


def reply(**fields):
    return parse_reply({"errorCode": "0", "errorMsg": "", "cmdName": "x", **fields})


def test_the_replies_are_read_as_the_sdk_reads_them():
    assert wire.reply_vout(reply(tio_vout_ena=1, tio_vout_vol=0)) == (1, 0)
    assert wire.reply_pin_mode(reply(pinMode=255)) == 255
    assert wire.reply_chn_mode(reply(chnMode=2)) == 2
    assert wire.reply_chn_comm(reply(slaveId=9, baudrate=115200, databit=8, stopbit=1,
                                     parity=78)) == (9, 115200, 8, 1, 78)
    rows = wire.reply_signals(reply(signals=[["grip_pos", 1, 3, 258, 500, 5]]))
    assert rows == (("grip_pos", 1, 3, 258, 500, 5),) and rows[0].value == 500
    assert wire.reply_signals(reply(signals=[])) == ()
    with pytest.raises(ProtocolError):                    # asInt on a string aborts the SDK
        wire.reply_pin_mode(reply(pinMode="255"))
    with pytest.raises(ProtocolError):                    # asString on a number aborts it
        wire.reply_signals(reply(signals=[[7, 1, 3, 258, 500, 5]]))
    with pytest.raises(CommandRejected):
        wire.reply_vout(parse_reply({"errorCode": "1", "errorMsg": "no", "cmdName": "x"}))


def test_the_packets_signals_are_read_when_the_packet_has_them():
    st = parse_status({"tio_rs_signals": [["grip_pos", 1, 3, 258, 500, 5],
                                          ["grip_state", 1, 3, 513, 2, 10]]})
    assert [r.value for r in st.tio_rs_signals] == [500, 2]
    assert parse_status({}).tio_rs_signals is None                     # fw 1.5.14's packet
    bad = parse_status({"tio_rs_signals": [["grip_pos", 1, "3", 258, 500, 5]]})
    assert bad.tio_rs_signals is None and "tio_rs_signals" in bad.malformed
