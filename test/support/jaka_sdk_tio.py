"""JAKA's SDK's twelve tool-connector (TIO) functions (libjakaAPI 2.1.14), restated for tests as
:mod:`jaka_sdk_model` restates the rest: each request encoded as the SDK encodes it (compact
JSON, sorted keys; docs/protocol.md "Tool connector" gives the measured forms), each reply read
as strictly as the SDK reads it. No set waits for a read-back (measured). ``SDK_REQUESTS`` are
the measured requests, byte for byte, for the fixtures.
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

from .jaka_sdk_json import as_int, as_string, element, member
from .jaka_sdk_model import RC_OK, JakaSdk

#: The requests as measured on the wire (sdk_wire_formats §10, restated in docs/protocol.md),
#: with the SDK call that sent each.
SDK_REQUESTS = {
    ("set_tio_vout_param", (1, 1)):
        '{"cmdName":"set_tio_vout_param","tio_vout_ena":1,"tio_vout_vol":1}',
    ("get_tio_vout_param", ()): '{"cmdName":"get_tio_vout_param"}',
    ("set_tio_pin_mode", (1, 18)): '{"cmdName":"set_tio_pin_mode","pinMode":18,"pinType":1}',
    ("get_tio_pin_mode", (1,)): '{"cmdName":"get_tio_pin_mode","pinType":1}',
    ("set_rs485_chn_mode", (1, 1)): '{"chnId":1,"chnMode":1,"cmdName":"set_rs485_chn_mode"}',
    ("get_rs485_chn_mode", (1,)): '{"chnId":1,"cmdName":"get_rs485_chn_mode"}',
    ("set_rs485_chn_comm", (0, 9, 115200, 8, 1, 78)):
        '{"baudrate":115200,"chn_id":0,"cmdName":"set_rs485_chn_comm","databit":8,'
        '"parity":78,"slaveId":9,"stopbit":1}',
    ("get_rs485_chn_comm", (0,)): '{"chn_id":0,"cmdName":"get_rs485_chn_comm"}',
    ("add_tio_rs_signal", ("grip_pos", 1, 3, 258, 5)):
        '{"cmdName":"add_tio_rs_signal","frequency":5,"tio_signal_chnId":1,'
        '"tio_signal_name":"grip_pos","tio_signal_sigAddr":258,"tio_signal_sigType":3}',
    ("del_tio_rs_signal", ("grip_pos",)):
        '{"cmdName":"del_tio_rs_signal","tio_signal_name":"grip_pos"}',
    ("send_tio_rs_command", (1, (1, 6, 1, 3, 255))):
        '{"chn_id":1,"cmdBuf":[1,6,1,3,255],"cmdName":"send_tio_rs_command"}',
    ("get_rs485_signal_info", ()): '{"cmdName":"get_tio_signals"}',
}

Row = Tuple[str, int, int, int, int, int]     # SignInfo: name, chn_id, sig_type, addr, value, Hz


class JakaSdkTio:
    """The twelve functions on one :class:`JakaSdk` handle (its connection and ``sent``)."""

    def __init__(self, sdk: JakaSdk):
        self.sdk = sdk

    def set_tio_vout_param(self, ena: int, vol: int) -> int:
        return self.sdk.call("set_tio_vout_param", tio_vout_ena=ena, tio_vout_vol=vol)[0]

    def get_tio_vout_param(self) -> Tuple[int, Tuple[int, int]]:
        rc, reply = self.sdk.call("get_tio_vout_param")
        if rc != RC_OK:
            return rc, (0, 0)
        return rc, (as_int(member(reply, "tio_vout_ena")), as_int(member(reply, "tio_vout_vol")))

    def set_tio_pin_mode(self, pin_type: int, mode: int) -> int:
        return self.sdk.call("set_tio_pin_mode", pinMode=mode, pinType=pin_type)[0]

    def get_tio_pin_mode(self, pin_type: int) -> Tuple[int, int]:
        rc, reply = self.sdk.call("get_tio_pin_mode", pinType=pin_type)
        return rc, as_int(member(reply, "pinMode")) if rc == RC_OK else 0

    def set_rs485_chn_mode(self, chn: int, mode: int) -> int:
        return self.sdk.call("set_rs485_chn_mode", chnId=chn, chnMode=mode)[0]

    def get_rs485_chn_mode(self, chn: int) -> Tuple[int, int]:
        rc, reply = self.sdk.call("get_rs485_chn_mode", chnId=chn)
        return rc, as_int(member(reply, "chnMode")) if rc == RC_OK else 0

    def set_rs485_chn_comm(self, chn: int, slave: int, baud: int, databit: int, stopbit: int,
                           parity: int) -> int:
        return self.sdk.call("set_rs485_chn_comm", baudrate=baud, chn_id=chn, databit=databit,
                             parity=parity, slaveId=slave, stopbit=stopbit)[0]

    def get_rs485_chn_comm(self, chn: int) -> Tuple[int, Tuple[int, int, int, int, int]]:
        rc, reply = self.sdk.call("get_rs485_chn_comm", chn_id=chn)
        if rc != RC_OK:
            return rc, (0, 0, 0, 0, 0)
        return rc, tuple(as_int(member(reply, k))
                         for k in ("slaveId", "baudrate", "databit", "stopbit", "parity"))

    def add_tio_rs_signal(self, name: str, chn: int, sig_type: int, addr: int,
                          frequency: int) -> int:
        return self.sdk.call("add_tio_rs_signal", frequency=frequency, tio_signal_chnId=chn,
                             tio_signal_name=name, tio_signal_sigAddr=addr,
                             tio_signal_sigType=sig_type)[0]

    def del_tio_rs_signal(self, name: str) -> int:
        return self.sdk.call("del_tio_rs_signal", tio_signal_name=name)[0]

    def send_tio_rs_command(self, chn: int, data: Sequence[int]) -> int:
        return self.sdk.call("send_tio_rs_command", chn_id=chn, cmdBuf=list(data))[0]

    def get_rs485_signal_info(self, capacity: int = 20) -> Tuple[int, List[Row]]:
        """``len`` in is the caller's capacity, the count out."""
        rc, reply = self.sdk.call("get_tio_signals")
        if rc != RC_OK:
            return rc, []
        signals = member(reply, "signals")
        rows = []
        for i in range(min(capacity, len(signals) if isinstance(signals, list) else 0)):
            row = element(signals, i)
            rows.append((as_string(element(row, 0)),
                         *(as_int(element(row, j)) for j in range(1, 6))))
        return rc, rows


def packet_signals(packet: dict) -> List[Row]:
    """The status packet's ``tio_rs_signals`` as the SDK reads it (rows of SignInfo)."""
    rows = member(packet, "tio_rs_signals")
    return [(as_string(element(r, 0)), *(as_int(element(r, j)) for j in range(1, 6)))
            for r in (rows or [])]
