"""The arm an emulated controller has: the model's nominal chain, another model's chain
(``--dh-from``: a controller whose arm is not the ``model`` a driver is started with), or a
calibrated one (``--calibration``: a parameter file, or a seed for a sub-millimetre
perturbation). The twin is built on that chain, so it moves as the controller's ``get_dh_param``
says and ``kine_forward`` / ``kine_inverse`` answer it; masses, limits and speeds stay the
model's.

A parameter file holds the ``dh_param`` rows of ``get_dh_param`` — alpha deg, a mm, d mm,
joint_homeoff deg, six each — as YAML or JSON, bare or under a ``dh_param`` key (a controller's
reply saved as it came).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np
import yaml

from ..common.models import RobotModel, load_model
from ..kinematics.calibrated_chain import perturbed, with_dh
from ..kinematics.controller_dh import DHParameters, dh_of_model


def arm_model(model: RobotModel, dh_from: Optional[str] = None,
              calibration: Optional[str] = None) -> RobotModel:
    """``model`` with the chain the options give it; ``model`` itself without either.
    ``calibration`` is an integer seed or a parameter file (it replaces ``dh_from``'s chain).
    ValueError names what is wrong."""
    if dh_from is None and calibration is None:
        return model
    dh = dh_of_model(load_model(dh_from) if dh_from else model)
    if calibration is not None:
        seed = _seed(calibration)
        dh = perturbed(dh, seed) if seed is not None else read_parameters(Path(calibration))
    return with_dh(model, dh)


def read_parameters(path: Path) -> DHParameters:
    """The ``dh_param`` rows of a file (see the module doc) as SI parameters."""
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise ValueError(f"calibration file {path}: {exc}") from None
    rows = data.get("dh_param") if isinstance(data, dict) else data
    try:
        alpha, a, d, home = (np.asarray(row, dtype=float) for row in rows)
        return DHParameters.from_sdk(np.radians(alpha), a, d, np.radians(home))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"calibration file {path}: expected dh_param, 4 rows of 6 numbers "
                         f"(alpha deg, a mm, d mm, joint_homeoff deg): {exc}") from None


def _seed(text: str) -> Optional[int]:
    try:
        return int(text)
    except ValueError:
        return None


__all__ = ["arm_model", "read_parameters"]
