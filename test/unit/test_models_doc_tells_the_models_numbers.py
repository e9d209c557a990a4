"""docs/models.md tells the numbers the driver uses: its model tables (payload, reach, arm mass,
torque limits; joint speeds, accelerations, TCP bounds) agree with load_model for all 22 models,
and its gallery shows every model's picture."""
import re
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model

DOC = (Path(__file__).resolve().parents[2] / "docs" / "models.md").read_text()


def _rows(header_start: str) -> dict[str, list[str]]:
    """The rows of the table whose header starts with ``header_start``, by model."""
    block = DOC[DOC.index(header_start):].split("\n\n")[0].splitlines()[2:]
    rows = {}
    for line in block:
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows[cells[0].strip("`")] = cells[1:]
    return rows


def _numbers(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?", text)]


SIZES = _rows("| model | structure | rated payload |")
LIMITS = _rows("| model | joint speed limits")


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_payload_reach_mass_and_torques_are_the_models(name):
    m = load_model(name)
    structure, payload, reach, mass, torque = SIZES[name]
    assert structure.lower().replace(" ", "_").startswith(m.structure.split("_")[0])
    assert _numbers(payload)[0] == m.rated_payload_kg
    assert _numbers(reach)[0] == m.reach_mm
    assert _numbers(mass)[0] == m.arm_mass_kg
    assert _numbers(torque) == [m.max_effort[0], m.max_effort[3]]


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_speeds_accelerations_and_tcp_bounds_are_the_models(name):
    m = load_model(name)
    speeds, accel, tcp_speed, tcp_accel = LIMITS[name]
    deg = _numbers(speeds)
    expected = np.degrees(m.max_velocity)
    np.testing.assert_allclose(deg * (6 if len(deg) == 1 else 1), expected, atol=0.6)
    np.testing.assert_allclose(_numbers(accel), np.degrees(m.max_acceleration[[0, 3]]), atol=0.6)
    assert _numbers(tcp_speed)[0] == pytest.approx(m.max_tcp_speed * 1000, rel=1e-12)   # mm/s
    assert _numbers(tcp_accel)[0] == pytest.approx(m.max_tcp_accel * 1000, rel=1e-12)


def test_the_gallery_shows_every_model():
    gallery = DOC[DOC.index("## Gallery"):].split("\n## ")[0]
    assert set(re.findall(r"images/jaka_(\w+)\.png", gallery)) == set(MODEL_NAMES)
