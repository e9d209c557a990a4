"""How the arm is mounted: tilted ``tilt_x`` about x, then turned ``rot_z`` about z — JAKA's
installation angle (docs/interface.md, "Mounting").

The base stays the frame of every pose; what turns is the world around it. The base's
orientation in the world is ``R = Rz(rot_z) · Rx(tilt_x)`` (RPY ``(tilt_x, 0, rot_z)``, as a
controller reads it back), and gravity in the base frame is ``Rᵀ (0, 0, −9.81)`` m/s²:
upright (0, 0) gravity is the base's −z; on a wall (90°, 0) it is the base's −y; on a ceiling
(180°, 0) +z. The ranges are JAKA's: tilt 0–180°, rotation 0–360°. Driver, twin and emulator
read a request through :func:`installation` (refusals -2 naming field, value and limit).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from .results import invalid
from .transforms import matrix_to_quat, rpy_to_matrix

#: m/s², gravity in the world (z up)
WORLD_GRAVITY = np.array([0.0, 0.0, -9.81])
TILT_RANGE = (0.0, math.pi)          # rad, about x
ROTATION_RANGE = (0.0, 2.0 * math.pi)  # rad, about z


@dataclass(frozen=True)
class Installation:
    """The base tilted ``tilt_x`` rad about x, then turned ``rot_z`` rad about z."""

    tilt_x: float = 0.0
    rot_z: float = 0.0

    @property
    def rotation(self) -> np.ndarray:
        """3x3, base → world."""
        return rpy_to_matrix(self.tilt_x, 0.0, self.rot_z)

    @property
    def gravity(self) -> np.ndarray:
        """m/s² in the base frame."""
        return self.rotation.T @ WORLD_GRAVITY

    @property
    def quaternion(self) -> np.ndarray:
        """The base's orientation in the world, (x, y, z, w)."""
        return matrix_to_quat(self.rotation)

    @property
    def rpy(self) -> np.ndarray:
        """The same as RPY, rad: ``(tilt_x, 0, rot_z)``."""
        return np.array([self.tilt_x, 0.0, self.rot_z])

    def describe(self) -> str:
        return (f"tilted {math.degrees(self.tilt_x):.1f}° about x, turned "
                f"{math.degrees(self.rot_z):.1f}° about z")


def installation(tilt_x: float, rot_z: float) -> Installation:
    """The mounting asked for, checked against JAKA's ranges (rad)."""
    for name, value, (lo, hi) in (("tilt_x", tilt_x, TILT_RANGE),
                                  ("rot_z", rot_z, ROTATION_RANGE)):
        limit = f"[{lo:g}, {hi:.6g}] rad ({math.degrees(lo):g}–{math.degrees(hi):g}°)"
        try:
            x = float(value)
        except (TypeError, ValueError):
            raise invalid(f"{name} is {value!r}, expected a number in {limit}") from None
        if not (math.isfinite(x) and lo - 1e-9 <= x <= hi + 1e-9):
            raise invalid(f"{name} is {x:g} rad ({math.degrees(x):g}°), expected {limit}")
    return Installation(min(max(float(tilt_x), TILT_RANGE[0]), TILT_RANGE[1]),
                        min(max(float(rot_z), ROTATION_RANGE[0]), ROTATION_RANGE[1]))


#: the frame above ``base_link`` in ``robot_description`` and TF: the world the arm is mounted in
WORLD_FRAME = "world"
_ROBOT_TAG = re.compile(r"<robot\b[^>]*>")


def mounted_description(urdf: str, mounting: Installation) -> str:
    """``urdf`` (rooted at ``base_link``) with a ``world`` link above it: the fixed joint
    ``world_joint`` turns the base as ``mounting`` says (origin RPY ``(tilt_x, 0, rot_z)``), so
    TF and rviz show the arm on its wall. The arm's own chain is unchanged."""
    tag = _ROBOT_TAG.search(urdf)
    if tag is None or 'name="base_link"' not in urdf:
        raise ValueError("not a URDF rooted at base_link")
    world = (f'\n  <link name="{WORLD_FRAME}"/>\n'
             f'  <joint name="{WORLD_FRAME}_joint" type="fixed">\n'
             f'    <parent link="{WORLD_FRAME}"/>\n    <child link="base_link"/>\n'
             f'    <origin xyz="0 0 0" rpy="{mounting.tilt_x!r} 0 {mounting.rot_z!r}"/>\n'
             f'  </joint>')
    return urdf[:tag.end()] + world + urdf[tag.end():]
