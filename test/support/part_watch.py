"""What the tests of the grippers watch of a part on a twin, and how they move the flange: the
part's place in the grasp frame recorded in the twin's own cycles, and straight moves by an
offset in the base frame. Shared by the pick on the twin and the pick through the emulator."""
from __future__ import annotations

import contextlib

import mujoco
import numpy as np

from jaka_driver.common.transforms import matrix_to_pose_mm


class PartWatch:
    """Where the part ``part`` is in ``site``'s frame (m) on ``backend`` (a SimBackend),
    recorded at the end of every cycle while ``on``. ``locked``: read under the physics lock
    (a twin on the wall clock, as the emulator's; a twin in sim time is read while the test
    holds its time)."""

    def __init__(self, backend, site: str, part: str = "box", locked: bool = False):
        m = backend._mj_model
        self.physics = backend._physics
        self.d = backend._physics.d
        self.part = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, part)
        self.site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, site)
        self.locked = locked
        self.on, self.offsets = False, []
        backend._physics.on_cycle.append(self._record)

    def _between_cycles(self):
        return self.physics.lock if self.locked else contextlib.nullcontext()

    def offset(self) -> np.ndarray:
        with self._between_cycles():
            return self._offset()

    def _offset(self) -> np.ndarray:
        d = self.d
        return d.site_xmat[self.site].reshape(3, 3).T @ (
            d.xpos[self.part] - d.site_xpos[self.site])

    def _record(self, _d):
        if self.on:
            self.offsets.append(self._offset())

    def position(self) -> np.ndarray:
        with self._between_cycles():
            return self.d.xpos[self.part].copy()

    def speed(self) -> float:
        with self._between_cycles():
            return float(np.linalg.norm(self.d.cvel[self.part][3:]))


def move_by(driver, dx=0.0, dy=0.0, dz=0.0, speed=100.0):
    """A straight move of the flange by (dx, dy, dz) mm in the base frame at ``speed`` mm/s."""
    pose = matrix_to_pose_mm(driver.state().tcp_pose)
    pose[:3] += (dx, dy, dz)
    result = driver.linear_move(list(pose), speed, 2500.0, coord_mode=1)
    assert result.ok, result.message
