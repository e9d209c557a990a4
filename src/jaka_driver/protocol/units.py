"""The unit edge between the JAKA TCP protocol and its callers.

On the wire (docs/protocol.md, "Units") joints are in **degrees** (speeds deg/s, accelerations
deg/s²) and Cartesian poses are ``[x, y, z, rx, ry, rz]`` in **mm** and **degrees**, the angles
being roll/pitch/yaw with ``R = Rz(rz) · Ry(ry) · Rx(rx)``.

The protocol library's API speaks the units of JAKA's own SDK: joints in **radians**, Cartesian
poses ``[x, y, z mm, rx, ry, rz rad]`` (the same RPY, in radians). So the only conversion here
is degrees ⇄ radians; rotation vectors and 4×4 matrices are the business of the callers (the
controller backend and the emulator convert through ``jaka_driver.common.transforms``). The protocol
package imports nothing else from the driver, so it can be used on its own.
"""
from __future__ import annotations

from typing import Iterable, List

import numpy as np


def deg_to_rad(values) -> np.ndarray:
    """Degrees (or deg/s, deg/s²) → radians (rad/s, rad/s²), elementwise, as a float array."""
    return np.radians(np.asarray(values, dtype=float))


def rad_to_deg(values) -> np.ndarray:
    """Radians (or rad/s, rad/s²) → degrees (deg/s, deg/s²), elementwise, as a float array."""
    return np.degrees(np.asarray(values, dtype=float))


def joints_to_wire(q_rad: Iterable[float]) -> List[float]:
    """Joint vector in rad → the wire's list of plain floats in degrees."""
    return [float(v) for v in rad_to_deg(list(q_rad))]


def joints_from_wire(q_deg: Iterable[float]) -> np.ndarray:
    """The wire's joint list in degrees → float array in rad."""
    return deg_to_rad(list(q_deg))


def pose_to_wire(pose_mm_rpy: Iterable[float]) -> List[float]:
    """``[x, y, z mm, rx, ry, rz rad]`` → wire ``[x, y, z mm, rx, ry, rz deg]``, plain floats."""
    p = np.asarray(list(pose_mm_rpy), dtype=float).reshape(6)
    return [float(v) for v in p[:3]] + [float(v) for v in np.degrees(p[3:])]


def pose_from_wire(wire_pose: Iterable[float]) -> np.ndarray:
    """Wire ``[x, y, z mm, rx, ry, rz deg]`` → ``[x, y, z mm, rx, ry, rz rad]``."""
    p = np.asarray(list(wire_pose), dtype=float).reshape(6)
    return np.concatenate([p[:3], np.radians(p[3:])])
