"""Modbus RTU frames as a tool connector carries them, read and written with pymodbus (its RTU
framer's CRC and its PDU codec), never a hand-written CRC.

Public code disagrees on whether a frame sent on a JAKA tool channel carries its CRC: JAKA's
demos send ``01 06 01 00 00 01`` (6 bytes, no CRC; the controller appends it), others send
the 8 bytes with it. A frame is read as carrying a CRC when its length is the request's PDU
plus slave id plus two; as one without when it is the PDU plus slave id; a frame whose CRC is
wrong is refused (None), as a gripper ignores it.
"""
from __future__ import annotations

from typing import NamedTuple, Optional, Sequence

from pymodbus.framer import FramerRTU
from pymodbus.pdu import DecodePDU
from pymodbus.pdu.register_message import (ReadHoldingRegistersRequest,
                                           WriteMultipleRegistersRequest,
                                           WriteSingleRegisterRequest)

_SERVER_DECODER = DecodePDU(is_server=True)
_FRAMER = FramerRTU(DecodePDU(is_server=True))


class Request(NamedTuple):
    """A request a slave received: its id, the function code, the first register and the
    values written (empty for a read; ``count`` registers read)."""

    slave: int
    function: int
    address: int
    values: tuple[int, ...]
    count: int
    crc: bool


def _pdu_length(pdu: bytes) -> Optional[int]:
    """The length of the request PDU that starts ``pdu`` (function code first), or None."""
    if not pdu:
        return None
    fc = pdu[0]
    if fc in (3, 4, 6):
        return 5
    if fc == 16 and len(pdu) >= 6:
        return 6 + pdu[5]
    return None


def read_request(frame: bytes) -> Optional[Request]:
    """The request in ``frame`` (6-byte-style without CRC, or with a right CRC), or None: a
    wrong CRC, a truncated frame, a function a gripper does not take."""
    frame = bytes(frame)
    if len(frame) < 2:
        return None
    length = _pdu_length(frame[1:])
    if length is None:
        return None
    if len(frame) == 1 + length + 2:
        used, slave, _, pdu = _FRAMER.decode(frame)
        if not pdu:
            return None          # the CRC is wrong
        crc = True
    elif len(frame) == 1 + length:
        slave, pdu, crc = frame[0], frame[1:], False
    else:
        return None
    try:
        message = _SERVER_DECODER.decode(pdu)
    except Exception:          # pymodbus raises on malformed PDUs
        return None
    if message is None:
        return None
    registers = tuple(int(v) for v in (getattr(message, "registers", None) or ()))
    fc = pdu[0]
    if fc in (3, 4):
        return Request(slave, fc, int(message.address), (), int(message.count), crc)
    return Request(slave, fc, int(message.address), registers, len(registers), crc)


def write_register(slave: int, address: int, value: int, crc: bool = False) -> bytes:
    """The frame writing ``value`` to holding register ``address`` of ``slave`` (FC06): 6
    bytes as JAKA's demos send it, or 8 with the CRC."""
    pdu_frame = _FRAMER.buildFrame(WriteSingleRegisterRequest(address=address,
                                                              registers=[int(value)],
                                                              dev_id=slave))
    return pdu_frame if crc else pdu_frame[:-2]


def write_registers(slave: int, address: int, values: Sequence[int], crc: bool = False) -> bytes:
    """FC16: ``values`` into consecutive holding registers from ``address``."""
    frame = _FRAMER.buildFrame(WriteMultipleRegistersRequest(
        address=address, registers=[int(v) for v in values], dev_id=slave))
    return frame if crc else frame[:-2]


def read_registers(slave: int, address: int, count: int = 1, crc: bool = False) -> bytes:
    """FC03: read ``count`` holding registers from ``address``."""
    frame = _FRAMER.buildFrame(ReadHoldingRegistersRequest(address=address, count=count,
                                                           dev_id=slave))
    return frame if crc else frame[:-2]
