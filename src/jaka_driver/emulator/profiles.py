"""Controller generations the emulator can be: what differs between the JAKA controllers on
record, selected by name (``--profile NAME``; docs/controller.md, "The emulator").

The default is the controller JAKA's current software is written for: firmware 1.7.x, which
JAKA's ROS 2 driver asks for (1.7.1 or newer) and whose ``emergency_stop_status`` JAKA's SDK
2.1.14 asks inside its moves, jogs and state calls (its calls fail where that answer is not a
success, as on the recorded fw 1.5.14). The recorded Zu 5s on fw 1.5.14 is one option away,
with every recorded quirk.

Everything here is evidence about a real controller or about what clients written from JAKA's
documents expect; each profile says which. What does not differ between them (commands, reply
layouts, the SDK's spellings) is the emulator's, for every profile. No profile removes a
command: no firmware on record lacks one the emulator answers.

The start state and the push period are a session's, not only a generation's (two of three
recorded sessions found the arm powered off, one found it on; the push period is a setting of
the controller): the profile gives their default, ``--start`` and ``--period`` override it.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping, Optional, Tuple

from ..common.constants import SERVO_CYCLE

#: Start states and what they are.
START_WORDS = {"off": "powered off and disabled", "on": "powered on, disabled",
               "enabled": "powered on and enabled"}
START_STATES = tuple(START_WORDS)

IoSizes = Mapping[Tuple[str, int, int], int]

#: The status packet of the Zu 5s recorded on fw 1.5.14, key by key (docs/protocol.md, "Status
#: packet", restating the recording: 36 keys with ``len``, 3208 bytes): its keys besides
#: ``len``, in the recording's order. Not in it: ``extio``, ``tio_key``, ``position``,
#: ``joint_position``, ``relay_io``, the fieldbus arrays, ``instVel``, ``motion_line``.
RECORDED_PACKET_KEYS: Tuple[str, ...] = (
    "drag_status", "errcode", "errmsg", "monitor_data", "torqsensor", "joint_actual_position",
    "actual_position", "din", "dout", "ain", "aout", "tio_din", "tio_dout", "tio_ain",
    "task_state", "homed", "task_mode", "interp_state", "enabled", "paused", "rapidrate",
    "current_tool_id", "current_user_id", "on_soft_limit", "emergency_stop", "drag_near_limit",
    "funcdi", "powered_on", "inpos", "motion_mode", "curr_tcp_trans_vel", "protective_stop",
    "point_key", "netState", "timestamp")


def _io_sizes(cabinet_digital: int, cabinet_analog: int, tool_analog_in: int,
              extension: bool) -> IoSizes:
    """(signal, type, path) → count: path 0 inputs, 1 outputs; types as JAKA's SDK numbers them
    (0 cabinet, 1 tool, 2 extension, 3 relay, 4 Modbus slave, 5 Profinet slave, 6 EtherNet/IP
    slave). ``extension``: an extension IO module (type 2) with the twin's 8 digital and 4
    analog points each way, reported in the packet's ``extio``."""
    sizes = {("digital", 0, 0): cabinet_digital, ("digital", 0, 1): cabinet_digital,
             ("analog", 0, 0): cabinet_analog, ("analog", 0, 1): cabinet_analog,
             ("digital", 1, 0): 8, ("digital", 1, 1): 8,
             ("analog", 1, 0): tool_analog_in, ("analog", 1, 1): 0,
             ("digital", 3, 1): 4}                     # relay outputs (relay_io)
    if extension:
        sizes.update({("digital", 2, 0): 8, ("digital", 2, 1): 8, ("analog", 2, 0): 4,
                      ("analog", 2, 1): 4})
    for bus in (4, 5, 6):                              # fieldbus slaves: 64 of each
        for signal in ("digital", "analog"):
            for path in (0, 1):
                sizes[(signal, bus, path)] = 64
    return MappingProxyType(sizes)


@dataclass(frozen=True)
class ControllerProfile:
    name: str
    summary: str                 # one line for --help and docs/controller.md
    version: str                 # get_version's "version"
    io_sizes: IoSizes
    din_status_count: int        # entries of get_digital_input_status
    period: float                # s between two status packets on port 10000
    start: str                   # one of START_STATES
    #: emergency_stop_status answers {"errorCode": "1", "errorMsg": "Exception:function call
    #: failed"} without cmdName (every recorded run of fw 1.5.14); else {"emergency_stop": 0|1}
    estop_status_fails: bool
    homed_count: int = 9         # entries of the packet's "homed"
    #: the status packet's keys (``len`` aside); None: every key the emulator has, each of them
    #: one JAKA's SDK 2.1.14 reads or JAKA's TCP protocol document lists
    packet_keys: Optional[Tuple[str, ...]] = None

    def describe(self) -> str:
        """What the profile sets, in one line (for --help and the log)."""
        din = self.io_sizes[("digital", 0, 0)]
        ain = self.io_sizes[("analog", 0, 0)]
        estop = ("answers the recorded exception" if self.estop_status_fails
                 else "answers emergency_stop")
        extension = "an" if self.io_sizes.get(("digital", 2, 0)) else "no"
        keys = ("every packet key JAKA's SDK reads" if self.packet_keys is None
                else f"the recorded packet's {len(self.packet_keys) + 1} keys")   # len too
        return (f"version {self.version}; cabinet digital IO {din}, analog {ain} each way, "
                f"{extension} extension IO module; {keys}; "
                f"a packet every {self.period * 1000:g} ms; starts {START_WORDS[self.start]}; "
                f"emergency_stop_status {estop}")


_RECORDED = ControllerProfile(
    name="zu5s-1.5.14",
    summary="the Zu 5s recorded on controller firmware 1.5.14, with its recorded answers "
            "(JAKA's SDK 2.1.14 fails its moves, jogs and state calls on it)",
    version="1.5.14_13_X64",
    # the recorded packet: no extension module (extio num 0)
    io_sizes=_io_sizes(cabinet_digital=135, cabinet_analog=64, tool_analog_in=2,
                       extension=False),
    din_status_count=64,
    # "about 30 ms per packet with default settings", measured by the author of a client
    # tested on that arm; 8 ms is the servo cycle, not the push period
    period=0.030,
    start="off",             # as two of the three recorded sessions found it
    estop_status_fails=True,
    packet_keys=RECORDED_PACKET_KEYS)
_FW_1_7 = ControllerProfile(
    name="fw-1.7.2",
    summary="a controller on firmware 1.7.2, the one JAKA's ROS 2 driver asks for (1.7.1 or "
            "newer) and JAKA's SDK 2.1.14 works with; its packet as JAKA's TCP protocol "
            "document gives it, a packet every servo cycle (the default)",
    version="1.7.2_16_X64",  # the version JAKA's ROS 2 driver recommends, recorded format
    io_sizes=_io_sizes(cabinet_digital=144, cabinet_analog=66, tool_analog_in=1,
                       extension=True),
    din_status_count=64,
    period=SERVO_CYCLE,
    start="enabled",
    estop_status_fails=False)
_LARGE_IO = dataclasses.replace(
    _FW_1_7, name="large-io",
    summary="the largest status packet on record (a newer controller with 200 cabinet digital "
            "IO and 128 analog each way); otherwise fw-1.7.2",
    io_sizes=_io_sizes(cabinet_digital=200, cabinet_analog=128, tool_analog_in=1,
                       extension=True))
_PROFILES = (_FW_1_7, _RECORDED, _LARGE_IO)

#: name → profile, in the order --help lists them.
PROFILES: Mapping[str, ControllerProfile] = MappingProxyType({p.name: p for p in _PROFILES})
DEFAULT_PROFILE = _FW_1_7.name
#: former names, still accepted: ``tcp-doc`` was fw-1.7.2's name before it became the default
ALIASES: Mapping[str, str] = MappingProxyType({"tcp-doc": _FW_1_7.name})


def profile_named(name: str) -> ControllerProfile:
    try:
        return PROFILES[ALIASES.get(name, name)]
    except KeyError:
        raise ValueError(f"unknown controller profile {name!r}; known: "
                         f"{', '.join(PROFILES)}") from None
