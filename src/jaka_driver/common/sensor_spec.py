"""A flange force/torque sensor as an arm's configuration describes it (``force_sensor:`` in
``config/<model>.yaml``, written by ``scripts/gen_urdf.py``): whether the arm carries one, its
range, and what the twin adds to its readings and puts under it.

Units: N and N·m (``range``, ``bias``, ``noise``: Fx Fy Fz Mx My Mz in the sensor frame, the
flange's), mm for the probe.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Mapping, Optional

import numpy as np


def _six(values, what: str) -> np.ndarray:
    a = np.array(values, dtype=float)
    if a.shape != (6,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{what}: expected 6 finite numbers (Fx Fy Fz N, Mx My Mz N·m), got "
                         f"{values!r}")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class ForceSensorSpec:
    """``mounted``: the arm carries the sensor (the node's ``~force_sensor`` overrides it);
    ``range`` the largest reading per axis (also the largest soft limit, condition and force
    a request may set); ``bias`` the offset an unzeroed sensor reads; ``noise`` the standard
    deviation of each sample; the twin's tool under the sensor is a capsule along flange z
    (``probe_length_mm`` from the flange to the centre of its tip, ``probe_radius_mm``) —
    what touches a table."""

    mounted: bool
    range: np.ndarray
    bias: np.ndarray
    noise: np.ndarray
    probe_length_mm: float
    probe_radius_mm: float

    def mounted_as(self, mounted: Optional[bool]) -> "ForceSensorSpec":
        """This sensor, mounted or not as ``mounted`` says (None: as configured)."""
        return self if mounted is None else replace(self, mounted=bool(mounted))


def sensor_spec(cfg: Optional[Mapping], where: str) -> ForceSensorSpec:
    """The ``force_sensor`` block of a model's configuration (``where`` names the file)."""
    if not isinstance(cfg, Mapping):
        raise ValueError(f"{where}: force_sensor must be a mapping (mounted, range, bias, noise, "
                         "probe)")
    probe = cfg.get("probe") or {}
    spec = ForceSensorSpec(
        mounted=bool(cfg.get("mounted", False)),
        range=_six(cfg["range"], f"{where}: force_sensor.range"),
        bias=_six(cfg.get("bias", [0.0] * 6), f"{where}: force_sensor.bias"),
        noise=_six(cfg.get("noise", [0.0] * 6), f"{where}: force_sensor.noise"),
        probe_length_mm=float(probe.get("length_mm", 100.0)),
        probe_radius_mm=float(probe.get("radius_mm", 10.0)))
    if np.any(spec.range <= 0) or np.any(spec.noise < 0):
        raise ValueError(f"{where}: force_sensor.range must be > 0 and noise ≥ 0")
    if not (spec.probe_length_mm > 0 and spec.probe_radius_mm > 0):
        raise ValueError(f"{where}: force_sensor.probe length_mm and radius_mm must be > 0")
    return spec
