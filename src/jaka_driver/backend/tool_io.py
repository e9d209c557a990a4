"""The tool connector every backend offers as ``backend.tool_io`` (:class:`ToolIO`): JAKA's TIO,
the connector on the flange a gripper hangs on — never None. A backend without one offers
:class:`NoToolIO`, which refuses every request with -9.

What it has (JAKA's header, ``JAKAZuRobot.h`` / ``jktypes.h``; docs/protocol.md "Tool
connector"):

* **the tool supply**: on/off and 24 V (code 0) or 12 V (code 1);
* **pin modes** per pin type (:class:`PinType`): the DI pins' mode 0x00–0x11 (a nibble per pin,
  0 NPN, 1 PNP); the DO pins' mode byte, high nibble DO2, low nibble DO1, each 0x0 NPN, 0x1 PNP,
  0x2 push-pull, 0xF RS485H (both nibbles 0xF: the DO pins are RS485 channel 0); the AI pins'
  mode 0 analog input, 1 RS485L (RS485 channel 1);
* **two RS485 channels**, 0 = RS485H, 1 = RS485L, each with a mode (:class:`ChannelMode`: 0
  Modbus RTU master, 1 raw RS485, 2 torque sensor) and comm parameters (:class:`ChannelComm`);
* **frames** sent on a channel (``send_tio_rs_command``: no reply bytes come back);
* **signals** (:class:`Signal`): Modbus registers the controller polls on a channel at up to
  10 Hz each, their latest values read with ``get_tio_signals``.

The rules — which values exist, when a frame may go out, what each refusal says — are written
here once (:func:`check_power` … :func:`frame_refusal`), and :class:`ToolIO`'s requests apply them
before its backend's transport (``_apply_…``) sees the request: the twin, the controller
backend and the emulator (which answers from the twin's facet) refuse alike. Every refusal is
-2 naming the field, the value and the limit; a refused request changes nothing. Each accepted
setting answers its read-back.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from enum import IntEnum
from functools import wraps
from typing import Optional, Sequence, Tuple

from ..common.results import Code, CommandRefused, Result, invalid

#: RS485 channel numbers, as JAKA's header numbers them for set_rs485_chn_mode
CHANNEL_NAMES = {0: "RS485H", 1: "RS485L"}
#: tio_vout_vol code → volts
VOLTAGES = {0: 24.0, 1: 12.0}
BAUD_MIN, BAUD_MAX = 4800, 230400
DATABITS = (7, 8)
STOPBITS = (1, 2)
#: parity byte → its letter: 'N' none, 'O' odd, 'E' even
PARITIES = {78: "N", 79: "O", 69: "E"}
#: Hz, a signal's highest polling frequency ("no more than 10", JAKA's header)
MAX_SIGNAL_HZ = 10
#: characters of a signal's name (SignInfo.sig_name[20] with its terminating zero)
MAX_NAME = 19
#: signals at once: the driver's own bound (none is on record for a controller); each is
#: polled every cycle it is due and carried by every state message
MAX_SIGNALS = 32
#: bytes of a frame: a Modbus RTU ADU's largest size
MAX_FRAME = 256
#: the DO pins' mode byte with both pins RS485H; the AI pins' mode RS485L
DO_RS485H = 0xFF
AI_RS485L = 1
#: a DO pin's nibble values: 0 NPN, 1 PNP, 2 push-pull, 0xF RS485H
DO_NIBBLES = (0x0, 0x1, 0x2, 0xF)
#: signal types: a Modbus holding register (FC03) and an input register (FC04)
SIGNAL_TYPES = {3: "holding register", 4: "input register"}


class PinType(IntEnum):
    """set_tio_pin_mode's ``pinType``."""

    DI = 0
    DO = 1
    AI = 2


class ChannelMode(IntEnum):
    """set_rs485_chn_mode's ``chnMode``."""

    MODBUS = 0
    RAW = 1
    TORQUE_SENSOR = 2


@dataclass(frozen=True)
class ChannelComm:
    """An RS485 channel's comm parameters (JAKA's ``ModRtuComm``): the Modbus slave id the
    channel talks to, baud rate (bit/s), data bits, stop bits, parity (78 'N', 79 'O', 69 'E')."""

    slave_id: int = 1
    baudrate: int = 115200
    databit: int = 8
    stopbit: int = 1
    parity: int = 78


@dataclass(frozen=True)
class Signal:
    """A Modbus register polled on a channel (JAKA's ``SignInfo``): ``name`` (≤ 19 characters),
    ``channel`` 0/1, ``sig_type`` 3 holding / 4 input register, ``address`` (0–65535), its latest
    ``value`` (0 until read) and ``frequency`` (Hz, 1–10)."""

    name: str
    channel: int
    sig_type: int
    address: int
    value: int = 0
    frequency: int = 1


@dataclass(frozen=True)
class ToolIOSettings:
    """What the tool connector is set to: the supply (``power_on``, ``voltage_code`` 0 = 24 V,
    1 = 12 V), the pin modes indexed by :class:`PinType`, the channels' modes and comm, indexed
    by channel. JAKA's defaults: supply off, DO pins NPN, AI pins analog, channels Modbus."""

    power_on: bool = False
    voltage_code: int = 0
    pin_modes: Tuple[int, int, int] = (0, 0, 0)
    channel_modes: Tuple[int, int] = (int(ChannelMode.MODBUS), int(ChannelMode.MODBUS))
    comm: Tuple[ChannelComm, ChannelComm] = field(
        default_factory=lambda: (ChannelComm(), ChannelComm()))

    @property
    def volts(self) -> float:
        """The supply's voltage now: 0.0 when off."""
        return VOLTAGES[self.voltage_code] if self.power_on else 0.0

    def in_rs485(self, channel: int) -> bool:
        """Whether the pins of ``channel`` are in RS485 mode."""
        if channel == 0:
            return self.pin_modes[PinType.DO] == DO_RS485H
        return self.pin_modes[PinType.AI] == AI_RS485L


# ---- the rules, written once -------------------------------------------------------------------
def _one_of(name: str, value, allowed, what: str = "") -> None:
    if value not in allowed:
        raise invalid(f"{name} is {value!r}, expected one of "
                      f"{', '.join(str(a) for a in allowed)}{what}")


def _int(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        try:
            as_int = int(value)
        except (TypeError, ValueError, OverflowError):
            raise invalid(f"{name} is {value!r}, expected an integer") from None
        if as_int != value:
            raise invalid(f"{name} is {value!r}, expected an integer")
        return as_int
    return value


def check_channel(channel, name: str = "channel") -> int:
    channel = _int(name, channel)
    _one_of(name, channel, tuple(CHANNEL_NAMES), " (0 = RS485H, 1 = RS485L)")
    return channel


def check_power(enabled, voltage_code) -> Tuple[bool, int]:
    """The supply: ``enabled`` 0/1, ``voltage_code`` 0 (24 V) or 1 (12 V)."""
    enabled = _int("enable", enabled)
    _one_of("enable", enabled, (0, 1))
    voltage_code = _int("voltage", voltage_code)
    _one_of("voltage", voltage_code, tuple(VOLTAGES), " (0 = 24 V, 1 = 12 V)")
    return bool(enabled), voltage_code


def voltage_code_of(volts) -> int:
    """The supply's voltage code of ``volts`` (24 → 0, 12 → 1), as a ROS request gives it."""
    for code, v in VOLTAGES.items():
        if volts == v:
            return code
    raise invalid(f"voltage is {volts!r} V, expected 24 or 12 V")


def check_pin_mode(pin_type, mode) -> Tuple[int, int]:
    pin_type = _int("pin_type", pin_type)
    _one_of("pin_type", pin_type, tuple(PinType), " (0 DI, 1 DO, 2 AI)")
    mode = _int("pin_mode", mode)
    if pin_type == PinType.DI:
        if mode & ~0x11 or mode < 0:
            raise invalid(f"pin_mode is {mode:#04x} for the DI pins, expected 0x00–0x11 (a "
                          f"nibble per pin: 0 NPN, 1 PNP)")
    elif pin_type == PinType.DO:
        if not 0 <= mode <= 0xFF or (mode >> 4) not in DO_NIBBLES or (mode & 0xF) not in DO_NIBBLES:
            raise invalid(f"pin_mode is {mode:#04x} for the DO pins, expected a nibble per pin "
                          f"(high DO2, low DO1) of 0x0 NPN, 0x1 PNP, 0x2 push-pull, 0xF RS485H")
    else:
        _one_of("pin_mode", mode, (0, AI_RS485L), " for the AI pins (0 analog input, 1 RS485L)")
    return pin_type, mode


def check_channel_mode(channel, mode) -> Tuple[int, int]:
    channel = check_channel(channel)
    mode = _int("channel_mode", mode)
    _one_of("channel_mode", mode, tuple(ChannelMode),
            " (0 Modbus RTU, 1 raw RS485, 2 torque sensor)")
    return channel, mode


def check_comm(channel, comm: ChannelComm) -> Tuple[int, ChannelComm]:
    channel = check_channel(channel)
    slave = _int("slave_id", comm.slave_id)
    if not 0 <= slave <= 247:
        raise invalid(f"slave_id is {slave}, expected 0–247 (Modbus RTU addresses)")
    baud = _int("baudrate", comm.baudrate)
    if not BAUD_MIN <= baud <= BAUD_MAX:
        raise invalid(f"baudrate is {baud}, expected {BAUD_MIN}–{BAUD_MAX} bit/s")
    databit = _int("databit", comm.databit)
    _one_of("databit", databit, DATABITS)
    stopbit = _int("stopbit", comm.stopbit)
    _one_of("stopbit", stopbit, STOPBITS)
    parity = _int("parity", comm.parity)
    _one_of("parity", parity, tuple(PARITIES), " (78 'N', 79 'O', 69 'E')")
    return channel, ChannelComm(slave, baud, databit, stopbit, parity)


def check_frame(channel, frame: Sequence[int]) -> Tuple[int, bytes]:
    """The frame's fields alone: a channel, 1–256 bytes each 0–255."""
    channel = check_channel(channel)
    values = list(frame)
    if not 1 <= len(values) <= MAX_FRAME:
        raise invalid(f"frame has {len(values)} bytes, expected 1–{MAX_FRAME}")
    data = []
    for i, b in enumerate(values):
        b = _int(f"frame[{i}]", b)              # 1.0 and -0.0 are whole: their int goes out
        if not 0 <= b <= 255:
            raise invalid(f"frame[{i}] is {b}, expected a byte 0–255")
        data.append(b)
    return channel, bytes(data)


def frame_refusal(settings: ToolIOSettings, channel: int) -> Optional[str]:
    """Why a frame may not go out on ``channel`` with these settings, or None: its pins must be
    in RS485 mode and its mode Modbus RTU or raw RS485."""
    name = CHANNEL_NAMES[channel]
    if not settings.in_rs485(channel):
        if channel == 0:
            mode = settings.pin_modes[PinType.DO]
            return (f"channel 0 ({name}): the DO pins' mode is {mode:#04x}, expected "
                    f"{DO_RS485H:#04x} (both pins RS485H; set_tio_pin_mode(1, 0xFF))")
        return (f"channel 1 ({name}): the AI pins' mode is "
                f"{settings.pin_modes[PinType.AI]}, expected {AI_RS485L} (RS485L; "
                f"set_tio_pin_mode(2, 1))")
    mode = settings.channel_modes[channel]
    if mode not in (ChannelMode.MODBUS, ChannelMode.RAW):
        return (f"channel {channel} ({name}): its mode is {mode} "
                f"({ChannelMode(mode).name.lower()}), expected 0 Modbus RTU or 1 raw RS485")
    return None


def check_signal(signal: Signal, existing: Sequence[Signal]) -> Signal:
    name = signal.name
    if not isinstance(name, str) or not name:
        raise invalid(f"name is {name!r}, expected 1–{MAX_NAME} characters")
    if len(name.encode()) > MAX_NAME:
        raise invalid(f"name {name!r} has {len(name.encode())} bytes, expected at most "
                      f"{MAX_NAME}")
    if any(s.name == name for s in existing):
        raise invalid(f"name {name!r} is a signal already (delete it first)")
    if len(existing) >= MAX_SIGNALS:
        raise invalid(f"signals: {len(existing)} already, at most {MAX_SIGNALS} (delete one "
                      f"first)")
    channel = check_channel(signal.channel)
    sig_type = _int("sig_type", signal.sig_type)
    _one_of("sig_type", sig_type, tuple(SIGNAL_TYPES), " (3 holding register, 4 input register)")
    address = _int("address", signal.address)
    if not 0 <= address <= 0xFFFF:
        raise invalid(f"address is {address}, expected 0–65535")
    frequency = _int("frequency", signal.frequency)
    if not 1 <= frequency <= MAX_SIGNAL_HZ:
        raise invalid(f"frequency is {frequency} Hz, expected 1–{MAX_SIGNAL_HZ} Hz")
    return Signal(name, channel, sig_type, address, 0, frequency)


# ---- the facet -------------------------------------------------------------------------------
def _answers(request):
    """A refusal raised by a rule or by the transport becomes its Result."""
    @wraps(request)
    def answered(self, *args) -> Result:
        try:
            return request(self, *args)
        except CommandRefused as refused:
            return refused.result()
    return answered


class ToolIO(ABC):
    """The tool connector (the module says what it has and which rules apply). Each request
    checks its fields and the connector's state, then hands the checked values to the
    backend's transport (``_apply_…``) and answers the read-back (``value``)."""

    @property
    def absent(self) -> Optional[str]:
        """Why there is no tool connector (the refusal's message), or None."""
        return None

    @abstractmethod
    def settings(self) -> ToolIOSettings:
        """What the connector is set to (as last read back)."""

    @abstractmethod
    def signals(self) -> Tuple[Signal, ...]:
        """Every signal with its latest value, in the order they were added."""

    @_answers
    def read_settings(self) -> Result:
        """The settings as the connector reports them now (a controller is asked each)."""
        return Result.success("tool connector settings", self._read_back())

    # ---- the requests: rules here, transport below ----------------------------------------
    @_answers
    def set_power(self, enabled, voltage_code) -> Result:
        """Tool supply on (``enabled`` 1) or off, at 24 V (``voltage_code`` 0) or 12 V (1)."""
        self._apply_power(*check_power(enabled, voltage_code))
        s = self._read_back()
        return Result.success(f"tool power {'on' if s.power_on else 'off'}, "
                              f"{VOLTAGES[s.voltage_code]:g} V", (s.power_on, s.voltage_code))

    @_answers
    def set_pin_mode(self, pin_type, mode) -> Result:
        """The mode of the DI, DO or AI pins (:class:`PinType`; the module says which modes)."""
        pin_type, mode = check_pin_mode(pin_type, mode)
        self._apply_pin_mode(pin_type, mode)
        mode = self._read_back().pin_modes[pin_type]
        return Result.success(f"{PinType(pin_type).name} pins' mode {mode:#04x}", mode)

    @_answers
    def set_channel_mode(self, channel, mode) -> Result:
        """RS485 channel ``channel``'s mode (:class:`ChannelMode`)."""
        channel, mode = check_channel_mode(channel, mode)
        self._apply_channel_mode(channel, mode)
        mode = self._read_back().channel_modes[channel]
        return Result.success(f"channel {channel} ({CHANNEL_NAMES[channel]}) mode {mode} "
                              f"({ChannelMode(mode).name.lower()})", mode)

    @_answers
    def set_channel_comm(self, channel, comm: ChannelComm) -> Result:
        """RS485 channel ``channel``'s slave id, baud rate, data bits, stop bits, parity."""
        channel, comm = check_comm(channel, comm)
        self._apply_comm(channel, comm)
        c = self._read_back().comm[channel]
        return Result.success(f"channel {channel} ({CHANNEL_NAMES[channel]}): slave "
                              f"{c.slave_id}, {c.baudrate} bit/s, {c.databit}"
                              f"{PARITIES.get(c.parity, '?')}{c.stopbit}", c)

    @_answers
    def send_frame(self, channel, frame: Sequence[int]) -> Result:
        """Send ``frame`` (bytes as given: a 6-byte Modbus request without CRC, as JAKA's demos
        send, or 8 with it) on ``channel``; refused (-9) unless its pins are in RS485 mode and
        its mode is Modbus RTU or raw."""
        channel, data = check_frame(channel, frame)
        why = frame_refusal(self.settings(), channel)
        if why is not None:
            raise CommandRefused(Code.WRONG_MODE, f"frame refused: {why}")
        self._apply_frame(channel, data)
        return Result.success(f"{len(data)} bytes sent on channel {channel} "
                              f"({CHANNEL_NAMES[channel]}): {data.hex(' ')}", len(data))

    @_answers
    def add_signal(self, signal: Signal) -> Result:
        """Poll a Modbus register as ``signal``; answers every signal."""
        checked = check_signal(signal, self.signals())
        self._apply_add_signal(checked)
        return Result.success(f"signal {checked.name!r}: {SIGNAL_TYPES[checked.sig_type]} "
                              f"{checked.address:#06x} on channel {checked.channel} at "
                              f"{checked.frequency} Hz", self._read_signals())

    @_answers
    def delete_signal(self, name: str) -> Result:
        """Stop polling the signal ``name``; answers the signals left."""
        if not any(s.name == name for s in self.signals()):
            names = ", ".join(repr(s.name) for s in self.signals()) or "none"
            raise invalid(f"name {name!r} is no signal (signals: {names})")
        self._apply_delete_signal(name)
        return Result.success(f"signal {name!r} deleted", self._read_signals())

    @_answers
    def read_signals(self) -> Result:
        """Every signal with its latest value (``get_tio_signals``)."""
        signals = self._read_signals()
        return Result.success(f"{len(signals)} signals", signals)

    # ---- the transport: each backend's own ---------------------------------------------------
    def _read_back(self) -> ToolIOSettings:
        """The settings as the connector reports them after a change (a controller asks it)."""
        return self.settings()

    def _read_signals(self) -> Tuple[Signal, ...]:
        return self.signals()

    @abstractmethod
    def _apply_power(self, enabled: bool, voltage_code: int) -> None: ...

    @abstractmethod
    def _apply_pin_mode(self, pin_type: int, mode: int) -> None: ...

    @abstractmethod
    def _apply_channel_mode(self, channel: int, mode: int) -> None: ...

    @abstractmethod
    def _apply_comm(self, channel: int, comm: ChannelComm) -> None: ...

    @abstractmethod
    def _apply_frame(self, channel: int, frame: bytes) -> None: ...

    @abstractmethod
    def _apply_add_signal(self, signal: Signal) -> None: ...

    @abstractmethod
    def _apply_delete_signal(self, name: str) -> None: ...


def with_value(signal: Signal, value: int) -> Signal:
    """``signal`` with its latest value read."""
    return replace(signal, value=int(value))


class NoToolIO(ToolIO):
    """An arm without a tool connector: every request is refused with -9 and ``reason``."""

    def __init__(self, reason: str):
        self._reason = reason

    @property
    def absent(self) -> Optional[str]:
        return self._reason

    def settings(self) -> ToolIOSettings:
        return ToolIOSettings()

    def signals(self) -> Tuple[Signal, ...]:
        return ()

    def _refuse(self, *_args) -> Result:
        return Result.failure(Code.WRONG_MODE, self._reason)

    set_power = set_pin_mode = set_channel_mode = set_channel_comm = send_frame = _refuse
    add_signal = delete_signal = read_signals = read_settings = _refuse

    def _apply(self, *_args) -> None:
        raise CommandRefused(Code.WRONG_MODE, self._reason)

    _apply_power = _apply_pin_mode = _apply_channel_mode = _apply_comm = _apply_frame = _apply
    _apply_add_signal = _apply_delete_signal = _apply
