"""The tool connector (TIO) and its RS485 channels on the wire (docs/protocol.md, "Tool
connector"): JAKA's SDK 2.1.14's twelve requests, keys in sorted order as it writes them, and
the replies as it reads them; the status packet's ``tio_rs_signals`` rows.

Values go out as given (codes, not volts: ``tio_vout_vol`` 0 = 24 V, 1 = 12 V); the ranges are
the caller's. Encoders check that each value is an integer (:class:`~.errors.InvalidArgument`,
nothing is sent); decoders raise :class:`~.errors.CommandRejected` for a refusal and
:class:`~.errors.ProtocolError` for a field of the wrong type — where the SDK would abort.
"""
from __future__ import annotations

from typing import Any, Dict, NamedTuple, Sequence, Tuple

from .errors import InvalidArgument, ProtocolError
from .fields import Cmd, Field
from .replies import Reply
from .reply_values import field as _field

Request = Dict[str, Any]


class SignalRow(NamedTuple):
    """One signal as the wire carries it (JAKA's ``SignInfo``)."""

    name: str
    channel: int
    sig_type: int
    address: int
    value: int
    frequency: int


def _int(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidArgument(f"{name} must be an integer; got {value!r}")
    return value


def _request(name: str, **fields) -> Request:
    """A request with its keys in sorted order, as JAKA's SDK writes them (jsoncpp)."""
    items = {Field.CMD_NAME: name, **{k: _int(k, v) for k, v in fields.items()}}
    return {key: items[key] for key in sorted(items)}


# ---- requests ----------------------------------------------------------------------------------
def set_tio_vout_param(enable: int, voltage_code: int) -> Request:
    return _request(Cmd.SET_TIO_VOUT_PARAM, **{Field.TIO_VOUT_ENA: enable,
                                               Field.TIO_VOUT_VOL: voltage_code})


def get_tio_vout_param() -> Request:
    return _request(Cmd.GET_TIO_VOUT_PARAM)


def set_tio_pin_mode(pin_type: int, mode: int) -> Request:
    return _request(Cmd.SET_TIO_PIN_MODE, **{Field.PIN_TYPE: pin_type, Field.PIN_MODE: mode})


def get_tio_pin_mode(pin_type: int) -> Request:
    return _request(Cmd.GET_TIO_PIN_MODE, **{Field.PIN_TYPE: pin_type})


def set_rs485_chn_mode(channel: int, mode: int) -> Request:
    return _request(Cmd.SET_RS485_CHN_MODE, **{Field.CHN_ID: channel, Field.CHN_MODE: mode})


def get_rs485_chn_mode(channel: int) -> Request:
    return _request(Cmd.GET_RS485_CHN_MODE, **{Field.CHN_ID: channel})


def set_rs485_chn_comm(channel: int, slave_id: int, baudrate: int, databit: int, stopbit: int,
                       parity: int) -> Request:
    return _request(Cmd.SET_RS485_CHN_COMM, **{
        Field.CHN_ID_COMM: channel, Field.SLAVE_ID: slave_id, Field.BAUDRATE: baudrate,
        Field.DATABIT: databit, Field.STOPBIT: stopbit, Field.PARITY: parity})


def get_rs485_chn_comm(channel: int) -> Request:
    return _request(Cmd.GET_RS485_CHN_COMM, **{Field.CHN_ID_COMM: channel})


def add_tio_rs_signal(name: str, channel: int, sig_type: int, address: int,
                      frequency: int) -> Request:
    """The signal's value is not sent (measured)."""
    if not isinstance(name, str):
        raise InvalidArgument(f"{Field.SIGNAL_NAME} must be a string; got {name!r}")
    request = _request(Cmd.ADD_TIO_RS_SIGNAL, **{
        Field.FREQUENCY: frequency, Field.SIGNAL_CHN_ID: channel,
        Field.SIGNAL_SIG_ADDR: address, Field.SIGNAL_SIG_TYPE: sig_type})
    request[Field.SIGNAL_NAME] = name
    return {key: request[key] for key in sorted(request)}


def del_tio_rs_signal(name: str) -> Request:
    if not isinstance(name, str):
        raise InvalidArgument(f"{Field.SIGNAL_NAME} must be a string; got {name!r}")
    return {Field.CMD_NAME: Cmd.DEL_TIO_RS_SIGNAL, Field.SIGNAL_NAME: name}


def send_tio_rs_command(channel: int, frame: Sequence[int]) -> Request:
    data = [_int(f"{Field.CMD_BUF}[{i}]", b) for i, b in enumerate(frame)]
    request = _request(Cmd.SEND_TIO_RS_COMMAND, **{Field.CHN_ID_COMM: channel})
    request[Field.CMD_BUF] = data
    return {key: request[key] for key in sorted(request)}


def get_tio_signals() -> Request:
    """JAKA's ``get_rs485_signal_info`` sends this."""
    return _request(Cmd.GET_TIO_SIGNALS)


# ---- replies -------------------------------------------------------------------------------------
def _reply_int(reply: Reply, key: str) -> int:
    raw = _field(reply, key)
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or int(raw) != raw:
        raise ProtocolError(f"{key!r} in the reply to {reply.cmd_name!r} is not an integer: "
                            f"{raw!r}")
    return int(raw)


def reply_vout(reply: Reply) -> Tuple[int, int]:
    """(enable 0/1, voltage code 0 = 24 V / 1 = 12 V)."""
    return _reply_int(reply, Field.TIO_VOUT_ENA), _reply_int(reply, Field.TIO_VOUT_VOL)


def reply_pin_mode(reply: Reply) -> int:
    return _reply_int(reply, Field.PIN_MODE)


def reply_chn_mode(reply: Reply) -> int:
    return _reply_int(reply, Field.CHN_MODE)


def reply_chn_comm(reply: Reply) -> Tuple[int, int, int, int, int]:
    """(slave id, baud rate, data bits, stop bits, parity)."""
    return tuple(_reply_int(reply, key) for key in (Field.SLAVE_ID, Field.BAUDRATE,
                                                     Field.DATABIT, Field.STOPBIT, Field.PARITY))


def signal_rows(raw: Any) -> Tuple[SignalRow, ...]:
    """``signals`` / ``tio_rs_signals``: rows [name, chn_id, sig_type, sig_addr, value,
    frequency]. Raises ``TypeError``/``ValueError`` for another shape."""
    if not isinstance(raw, list):
        raise TypeError("signals is not a list")
    rows = []
    for row in raw:
        if not isinstance(row, list) or len(row) < 6 or not isinstance(row[0], str):
            raise ValueError(f"a signal row is [name, chn_id, sig_type, sig_addr, value, "
                             f"frequency]; got {row!r}")
        numbers = row[1:6]
        if any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in numbers):
            raise ValueError(f"a signal row's numbers are not numbers: {row!r}")
        rows.append(SignalRow(row[0], *(int(v) for v in numbers)))
    return tuple(rows)


def reply_signals(reply: Reply) -> Tuple[SignalRow, ...]:
    raw = _field(reply, Field.SIGNALS)
    try:
        return signal_rows(raw)
    except (TypeError, ValueError) as exc:
        raise ProtocolError(f"{Field.SIGNALS!r} in the reply to {reply.cmd_name!r}: "
                            f"{exc}") from None
