"""Random arm configurations for the motion benchmarks, away from the floor.

Drawn around JAKA's ``pose_1`` (the twin's start pose) with a fixed RNG seed, so every run
moves the same way. A configuration is kept when the origins of J3 … J6 (elbow and wrist;
J1 and J2 sit on the base) are at least ``MIN_HEIGHT_M`` above the mounting plane (Pinocchio
FK on the model's URDF).
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin

HOME = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0])
MIN_HEIGHT_M = 0.15


class PoseSampler:
    def __init__(self, model, seed: int):
        self.model = model
        self._pin = pin.buildModelFromXML(model.urdf_xml)
        self._data = self._pin.createData()
        self.rng = np.random.default_rng(seed)

    def clear_of_floor(self, q: np.ndarray) -> bool:
        pin.forwardKinematics(self._pin, self._data, q)
        return all(self._data.oMi[i].translation[2] >= MIN_HEIGHT_M
                   for i in range(3, self._pin.njoints))

    def near_home(self, spread_rad: float) -> np.ndarray:
        """A configuration within ±``spread_rad`` of ``HOME`` per joint, inside the limits
        and clear of the floor."""
        lo, hi = np.asarray(self.model.lower), np.asarray(self.model.upper)
        for _ in range(10_000):
            q = np.clip(HOME + self.rng.uniform(-spread_rad, spread_rad, 6), lo, hi)
            if self.clear_of_floor(q):
                return q
        raise RuntimeError(f"no configuration within ±{spread_rad} rad of pose_1 is "
                           f"{MIN_HEIGHT_M} m clear of the floor")
