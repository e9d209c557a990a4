"""A hand on the twin's tool: a wrench applied to the tool for a while (``backend.twin.
push_tool``), as an operator pushes a real arm — what a force/torque sensor, tool drive and
admittance feel.

The wrench (Fx Fy Fz N, Mx My Mz N·m) is along the base's axes with the force acting at the
flange centre (the sensor's origin). MuJoCo applies a body's external force at its centre of
mass (``xfrc_applied``), so each cycle the moment is moved there: ``M + (flange − com) × F``.
Applied from the cycle after the push starts, for its duration in the twin's time (whole 8 ms
cycles), then released. Units: N, N·m, s.
"""
from __future__ import annotations

import mujoco
import numpy as np


class ToolPush:
    """Pushes on ``body`` (the sensor's tool side, or the flange body) of ``d``; call
    :meth:`apply` once per cycle (physics thread), :meth:`start` under the physics lock."""

    def __init__(self, m: mujoco.MjModel, body: str):
        self._body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, body)
        if self._body < 0:
            raise ValueError(f"the twin has no body {body!r} to push")
        self._wrench = np.zeros(6)
        self._cycles = 0

    def start(self, d: mujoco.MjData, wrench: np.ndarray, cycles: int) -> None:
        """Push with ``wrench`` for ``cycles`` cycles (0: release now)."""
        self._wrench = np.asarray(wrench, float).copy()
        self._cycles = int(cycles)
        self._write(d)

    @property
    def pushing(self) -> bool:
        return self._cycles > 0

    def apply(self, d: mujoco.MjData) -> None:
        """A cycle has run: count it, and set the push for the next one."""
        if self._cycles > 0:
            self._cycles -= 1
            self._write(d)

    def _write(self, d: mujoco.MjData) -> None:
        b = self._body
        if self._cycles <= 0:
            d.xfrc_applied[b] = 0.0
            return
        force = self._wrench[:3]
        d.xfrc_applied[b, :3] = force
        d.xfrc_applied[b, 3:] = self._wrench[3:] + np.cross(d.xpos[b] - d.xipos[b], force)
