"""The arm's mounting: ``set_installation_angle`` and ``get_installation_angle``, as JAKA's SDK
2.1.14 writes and reads them (docs/protocol.md, "Mounting").

* set: ``{"angleX":28.64788975654116,"angleZ":57.29577951308232,"cmdName":
  "set_installation_angle"}`` — the tilt about x and the rotation about z in **deg**, written
  with 16 significant digits (the SDK takes rad); the reply carries only ``errorCode``.
* get: ``"installation_angle":[[s, x, y, z], [rx, ry, rz]]`` — row 0 the quaternion, scalar
  first, row 1 the same rotation as RPY in deg; a flat list or an object crashes JAKA's SDK.

Here angles are rad and quaternions ``(x, y, z, w)``, as everywhere in the library's API.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .errors import ProtocolError
from .fields import Cmd, Field
from .replies import Reply
from .reply_values import field as _field
from .request_values import Request, command as _cmd, number as _number
from .wire import float_vector


def _sixteen_digits(x: float) -> float:
    """``x`` rounded to the 16 significant digits JAKA's SDK writes."""
    return float(f"{x:.16g}")


def set_installation_angle(tilt_x_rad: float, rot_z_rad: float) -> Request:
    """The arm tilted ``tilt_x_rad`` about x, then turned ``rot_z_rad`` about z (rad)."""
    x = _number(tilt_x_rad, "installation tilt about x (rad)")
    z = _number(rot_z_rad, "installation rotation about z (rad)")
    return _cmd(Cmd.SET_INSTALLATION_ANGLE,
                **{Field.ANGLE_X: _sixteen_digits(math.degrees(x)),
                   Field.ANGLE_Z: _sixteen_digits(math.degrees(z))})


def get_installation_angle() -> Request:
    """Reply: :func:`reply_installation_angle`."""
    return _cmd(Cmd.GET_INSTALLATION_ANGLE)


class InstallationReading(NamedTuple):
    """What ``get_installation_angle`` answers: ``quaternion`` (x, y, z, w) and ``rpy`` (rad)."""
    quaternion: np.ndarray
    rpy: np.ndarray


def reply_installation_angle(reply: Reply) -> InstallationReading:
    """``get_installation_angle`` → quaternion (x, y, z, w) and RPY (rad)."""
    raw = _field(reply, Field.INSTALLATION_ANGLE)
    rows = raw if isinstance(raw, list) and len(raw) == 2 else None
    quat = float_vector(rows[0], 4) if rows else None
    rpy = float_vector(rows[1], 3) if rows else None
    if quat is None or rpy is None:
        raise ProtocolError(f"{Field.INSTALLATION_ANGLE!r} should be [[s, x, y, z], "
                            f"[rx, ry, rz]]; got {str(raw)[:200]}")
    return InstallationReading(np.array([quat[1], quat[2], quat[3], quat[0]]), np.radians(rpy))


def installation_reply(quaternion_xyzw, rpy_rad) -> dict:
    """The reply field for a controller's side (the emulator): ``installation_angle`` from a
    quaternion (x, y, z, w) and RPY (rad)."""
    x, y, z, w = (float(v) for v in quaternion_xyzw)
    return {Field.INSTALLATION_ANGLE: [[w, x, y, z], [float(math.degrees(a)) for a in rpy_rad]]}
