"""Trajectory recording on the wire (docs/protocol.md, "Trajectory recording"): JAKA's SDK's
eight functions as SDK 2.1.14 writes their requests (keys sorted, compact) and reads their
replies.

* ``set_traj_config`` — ``xyz_interval`` (mm) and ``rpy_interval`` (deg) with **2 decimals**,
  ``vel`` (mm/s) and ``acc`` (mm/s²) as plain doubles, all unconverted;
  ``get_traj_config`` answers the same four keys as doubles.
* ``set_traj_sample_mode`` — ``filename`` and ``mode`` (1 start, 0 stop);
  ``get_traj_sample_status`` answers ``sampleStatus``, an **int**.
* ``get_exist_traj_file_name`` answers ``trajTrackFileName``, a list of strings (JAKA's SDK
  reads at most :data:`MAX_NAMES`).
* ``rename_traj_file_name`` — ``src``, ``dest``; ``generate_traj_exe_file`` and
  ``remove_traj_file`` — ``fileName``. The generated program loads as ``track/<name>``.

Every reply's ``errorCode`` is a string. Decoders raise :class:`~.errors.CommandRejected` for
a refusal and :class:`~.errors.ProtocolError` where JAKA's SDK would abort its client (a
string for a number, a number for a name, a scalar for the list).
"""
from __future__ import annotations

import math
from typing import Any, Dict, List, NamedTuple

from .errors import InvalidArgument, ProtocolError
from .fields import Cmd, Field
from .replies import Reply
from .reply_values import field as _field
from .request_values import command as _cmd, number as _number
from .wire import Fixed

Request = Dict[str, Any]
#: decimals JAKA's SDK writes the two intervals with (measured: "xyz_interval":0.10)
INTERVAL_DECIMALS = 2
#: the most names JAKA's SDK reads from ``get_exist_traj_file_name`` (more: rc −15)
MAX_NAMES = 256


class TrajConfigWire(NamedTuple):
    """``get_traj_config``'s values as the wire has them: mm, deg, mm/s, mm/s²."""

    xyz_interval: float
    rpy_interval: float
    vel: float
    acc: float


def _sorted(name: str, **fields) -> Request:
    """A request with its keys in sorted order, as JAKA's SDK writes them (jsoncpp)."""
    items = _cmd(name, **fields)
    return {key: items[key] for key in sorted(items)}


def _name(value, what: str) -> str:
    if not isinstance(value, str):
        raise InvalidArgument(f"{what} must be a string; got {value!r}")
    return value


def set_traj_config(xyz_interval_mm: float, rpy_interval_deg: float, vel_mm_s: float,
                    acc_mm_s2: float) -> Request:
    """The sampling thresholds and the replay's speed and acceleration, unconverted; the
    intervals go out with 2 decimals."""
    return _sorted(Cmd.SET_TRAJ_CONFIG, **{
        Field.XYZ_INTERVAL: Fixed(_number(xyz_interval_mm, "xyz_interval", positive=True),
                                  INTERVAL_DECIMALS),
        Field.RPY_INTERVAL: Fixed(_number(rpy_interval_deg, "rpy_interval", positive=True),
                                  INTERVAL_DECIMALS),
        Field.TRAJ_VEL: _number(vel_mm_s, "vel", positive=True),
        Field.TRAJ_ACC: _number(acc_mm_s2, "acc", positive=True)})


def get_traj_config() -> Request:
    """Reply: :func:`reply_traj_config`."""
    return _cmd(Cmd.GET_TRAJ_CONFIG)


def _double(reply: Reply, key: str) -> float:
    raw = _field(reply, key)
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw):
        raise ProtocolError(f"{key!r} in the reply to {reply.cmd_name!r} is not a finite "
                            f"number: {raw!r}")
    return float(raw)


def reply_traj_config(reply: Reply) -> TrajConfigWire:
    return TrajConfigWire(*(_double(reply, key) for key in (
        Field.XYZ_INTERVAL, Field.RPY_INTERVAL, Field.TRAJ_VEL, Field.TRAJ_ACC)))


def set_traj_sample_mode(on: bool, filename: str) -> Request:
    """Start (``on``) recording as ``filename``, or stop."""
    return _sorted(Cmd.SET_TRAJ_SAMPLE_MODE, **{Field.TRAJ_FILENAME: _name(filename, "filename"),
                                                Field.TRAJ_MODE: 1 if on else 0})


def get_traj_sample_status() -> Request:
    """Reply: :func:`reply_traj_sample_status`."""
    return _cmd(Cmd.GET_TRAJ_SAMPLE_STATUS)


def reply_traj_sample_status(reply: Reply) -> bool:
    """``sampleStatus``, an int (a bool is read as JAKA's SDK's ``asInt`` reads it)."""
    raw = _field(reply, Field.SAMPLE_STATUS)
    if not isinstance(raw, (int, float)) or (isinstance(raw, float) and not math.isfinite(raw)):
        raise ProtocolError(f"{Field.SAMPLE_STATUS!r} in the reply to {reply.cmd_name!r} is "
                            f"not an int: {raw!r}")
    return int(raw) != 0


def get_exist_traj_file_name() -> Request:
    """Reply: :func:`reply_traj_file_names`."""
    return _cmd(Cmd.GET_EXIST_TRAJ_FILE_NAME)


def reply_traj_file_names(reply: Reply) -> List[str]:
    raw = _field(reply, Field.TRAJ_FILE_NAMES)
    if not isinstance(raw, list) or not all(isinstance(n, str) for n in raw):
        raise ProtocolError(f"{Field.TRAJ_FILE_NAMES!r} in the reply to {reply.cmd_name!r} "
                            f"is not a list of names: {str(raw)[:200]}")
    if len(raw) > MAX_NAMES:
        raise ProtocolError(f"{Field.TRAJ_FILE_NAMES!r} has {len(raw)} names, JAKA's SDK "
                            f"reads at most {MAX_NAMES}")
    return list(raw)


def rename_traj_file_name(src: str, dest: str) -> Request:
    return _sorted(Cmd.RENAME_TRAJ_FILE_NAME, **{Field.TRAJ_DEST: _name(dest, "dest"),
                                                 Field.TRAJ_SRC: _name(src, "src")})


def remove_traj_file(name: str) -> Request:
    return _sorted(Cmd.REMOVE_TRAJ_FILE, **{Field.TRAJ_FILE_NAME: _name(name, "fileName")})


def generate_traj_exe_file(name: str) -> Request:
    """The replay program of recording ``name``, then loaded as ``track/<name>``."""
    return _sorted(Cmd.GENERATE_TRAJ_EXE_FILE,
                   **{Field.TRAJ_FILE_NAME: _name(name, "fileName")})
