"""JAKA's SDK's eight trajectory-recording functions (libjakaAPI 2.1.14), restated for tests
beside :mod:`jaka_sdk_model` from the measurements of docs/protocol.md ("Trajectory
recording"): each request exactly as the SDK writes it (sorted keys, compact, the two intervals
with 2 decimals, vel and acc with 16 significant digits), each reply read as strictly:

* ``errorCode`` must be a **string** here: an int aborts the client (:class:`SdkCrash`); "0"
  is rc 0, any other string rc 2 with the output untouched;
* ``get_traj_config``: four doubles (a string aborts, a missing key reads 0);
* ``get_traj_sample_status``: ``sampleStatus`` an int (a string aborts);
* ``get_exist_traj_file_name``: ``trajTrackFileName`` a list of strings, names cut to 255
  characters, more than 256 names rc −15, a non-string element aborts, an object crashes;
* ``set_traj_sample_mode`` with no name returns −30 and sends nothing.
"""
from __future__ import annotations

from typing import Any, List, Optional, Tuple

from .jaka_sdk_json import SdkCrash, as_double, as_int, as_string, element, member
from .jaka_sdk_model import RC_FAILED, RC_OK, JakaSdk

RC_NULL_NAME = -30
RC_TOO_MANY = -15


def traj_rc(reply: Any) -> int:
    """The rc of one of these replies: a string errorCode, as the SDK needs it here."""
    code = member(reply, "errorCode")
    if isinstance(code, (int, float)) and not isinstance(code, bool):
        raise SdkCrash(f"errorCode {code!r} is a number: asString aborts the client")
    if not isinstance(code, str):
        return RC_FAILED
    try:
        return RC_OK if int(code) == 0 else RC_FAILED
    except ValueError:
        return RC_FAILED


class SdkRecording:
    """The eight functions on a :class:`~jaka_sdk_model.JakaSdk` handle's command connection."""

    def __init__(self, sdk: JakaSdk):
        self.sdk = sdk

    def _call(self, command: str, **fields) -> Tuple[int, dict]:
        _, reply = self.sdk.call(command, **fields)
        return traj_rc(reply), reply

    def set_traj_config(self, xyz_interval: float, rpy_interval: float, vel: float,
                        acc: float) -> int:
        """The intervals go out with 2 decimals (jaka_sdk_json.FIXED_DECIMALS)."""
        return self._call("set_traj_config", xyz_interval=float(xyz_interval),
                          rpy_interval=float(rpy_interval), vel=float(vel), acc=float(acc))[0]

    def get_traj_config(self) -> Tuple[int, Optional[Tuple[float, float, float, float]]]:
        rc, reply = self._call("get_traj_config")
        if rc != RC_OK:
            return rc, None
        return rc, tuple(as_double(member(reply, k))
                         for k in ("xyz_interval", "rpy_interval", "vel", "acc"))

    def set_traj_sample_mode(self, mode: bool, filename: Optional[str]) -> int:
        if filename is None:
            return RC_NULL_NAME
        return self._call("set_traj_sample_mode", filename=filename, mode=int(bool(mode)))[0]

    def get_traj_sample_status(self) -> Tuple[int, Optional[int]]:
        rc, reply = self._call("get_traj_sample_status")
        return rc, as_int(member(reply, "sampleStatus")) if rc == RC_OK else None

    def get_exist_traj_file_name(self) -> Tuple[int, Optional[List[str]]]:
        rc, reply = self._call("get_exist_traj_file_name")
        if rc != RC_OK:
            return rc, None
        names = member(reply, "trajTrackFileName")
        if isinstance(names, dict):
            raise SdkCrash("trajTrackFileName is an object: the client crashes")
        count = len(names) if isinstance(names, list) else 0
        if count > 256:
            return RC_TOO_MANY, None
        read = []
        for i in range(count):
            item = element(names, i)
            if not isinstance(item, str):
                raise SdkCrash(f"trajTrackFileName[{i}] is {item!r}: asString aborts")
            read.append(as_string(item)[:255])
        return rc, read

    def rename_traj_file_name(self, src: str, dest: str) -> int:
        return self._call("rename_traj_file_name", src=src, dest=dest)[0]

    def remove_traj_file(self, name: str) -> int:
        return self._call("remove_traj_file", fileName=name)[0]

    def generate_traj_exe_file(self, name: str) -> int:
        return self._call("generate_traj_exe_file", fileName=name)[0]
