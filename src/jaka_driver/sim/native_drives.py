"""The compiled twin cycle (``joint_drives.c`` beside this file), through ctypes.

:class:`jaka_driver.sim.servo.JointServo` keeps its setpoints in a :class:`Drives` structure
and, when the library is here, steps each 8 ms cycle with one C call: the drives' set-up,
``mj_step`` × 8 and the torques and following error the checks read. Without the library, or
with one built for another MuJoCo, :func:`load` answers None and ``JointServo`` computes the
same numbers in numpy, only slower.

``make setup`` compiles ``devel/lib/libjaka_drives.so`` against the headers and the
``libmujoco`` of the venv's ``mujoco`` package (``JAKA_DRIVES_LIB`` names another file).
"""
from __future__ import annotations

import ctypes
import functools
from pathlib import Path
from typing import Optional

import mujoco

from ..host import native_library

LIBRARY = "libjaka_drives.so"
JOINTS = 6
_Joints = ctypes.c_double * JOINTS


class Drives(ctypes.Structure):
    """``jd_drives`` of joint_drives.c, field for field (rad, rad/s, rad/s², N·m, s)."""

    _fields_ = [("kp", _Joints), ("kd", _Joints), ("damping", _Joints),
                ("drag_damping", ctypes.c_double), ("cycle", ctypes.c_double),
                ("diag", ctypes.c_int * JOINTS), ("steps", ctypes.c_int),
                ("released", ctypes.c_int),
                ("from_", _Joints), ("to", _Joints), ("velocity", _Joints), ("accel", _Joints),
                ("next", _Joints), ("tau", _Joints), ("lag", ctypes.c_double), ("lag_joint", ctypes.c_int)]


def library_path() -> Path:
    """``$JAKA_DRIVES_LIB``, else where :func:`jaka_driver.host.native_library.path` finds it."""
    return native_library.path(LIBRARY, "JAKA_DRIVES_LIB")


class NativeDrives:
    """The two entry points of the library. ``cycle`` releases the interpreter lock for the
    whole cycle (ctypes.CDLL); ``new_setpoint``, a few dozen nanoseconds of work, keeps it
    (ctypes.PyDLL: no lock hand-over for so little)."""

    def __init__(self, released: ctypes.CDLL, path: Path):
        held = ctypes.PyDLL(str(path))      # the same library, its calls keeping the lock
        self.cycle = released.jd_cycle
        self.cycle.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
        self.cycle.restype = None
        self.new_setpoint = held.jd_new_setpoint
        self.new_setpoint.argtypes = [ctypes.c_void_p]
        self.new_setpoint.restype = None


@functools.lru_cache(maxsize=None)
def load() -> Optional[NativeDrives]:
    """The compiled cycle (opened once per process, which says where it came from), or None
    when the library is not built, does not open, was built from another joint_drives.c or
    against another MuJoCo (its structures could be laid out otherwise: never guess)."""
    return native_library.opened(library_path(), _open, "twin cycle library",
                                 "the twin steps its cycle in numpy")


def _open(path: Path) -> Optional[NativeDrives]:
    if not path.is_file():
        return None
    try:
        lib = ctypes.CDLL(str(path))
        if (lib.jd_drives_size() != ctypes.sizeof(Drives)
                or lib.jd_mujoco_version() != mujoco.mj_version()):
            return None
        return NativeDrives(lib, path)
    except (OSError, AttributeError):
        return None
