"""Parts to pick: the movable bodies of a workcell file's ``parts:`` list.

Each is given as an obstacle is (``name``, ``type`` box / cylinder / sphere, ``size`` MuJoCo
half-sizes in m, ``pos`` m in the base frame, ``euler`` rad, ``rgba``) plus ``mass`` (kg) and
``friction`` (sliding, default 0.8): a body of the twin with a free joint, so it falls, rests,
collides with the floor, the obstacles, the arm and the gripper, and can be held. Where the
scene places it is its pose in MuJoCo's reference configuration, so the twin's reset
(``mj_resetData``) puts every part back there.

:class:`PartPoses` reads where they are now (4x4 poses, m, base frame).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import mujoco
import numpy as np

GEOM_TYPES = {"box": mujoco.mjtGeom.mjGEOM_BOX, "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
              "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER}
DEFAULT_FRICTION = 0.8


def scene_parts(scene: Optional[str]) -> list[dict]:
    """The ``parts:`` entries of a YAML workcell file (none for no file or an MJCF one),
    checked: a wrong type, size or mass is refused with the part and the field."""
    if not scene or Path(scene).suffix.lower() in (".xml", ".mjcf"):
        return []
    import yaml
    data = yaml.safe_load(Path(scene).read_text()) or {}
    parts = []
    for i, item in enumerate(data.get("parts", []) or []):
        name = str(item.get("name", f"part_{i}"))
        kind = item.get("type", "box")
        if kind not in GEOM_TYPES:
            raise ValueError(f"{scene}: part {name} has type {kind!r}, expected one of "
                             f"{', '.join(GEOM_TYPES)}")
        mass = float(item.get("mass", 0.1))
        if not mass > 0.0:
            raise ValueError(f"{scene}: part {name} has mass {mass} kg, expected > 0")
        size = [float(v) for v in item["size"]]
        if not size or min(size) <= 0.0:
            raise ValueError(f"{scene}: part {name} has size {size}, expected half-sizes > 0 m")
        parts.append({"name": name, "type": kind, "size": size, "mass": mass,
                      "pos": [float(v) for v in item.get("pos", [0, 0, 0])],
                      "euler": [float(v) for v in item.get("euler", [0, 0, 0])],
                      "friction": float(item.get("friction", DEFAULT_FRICTION)),
                      "rgba": list(item.get("rgba", [0.2, 0.5, 0.8, 1.0]))})
    return parts


def part_names(scene: Optional[str]) -> list[str]:
    """The names of the scene's parts (its bodies in the twin)."""
    return [part["name"] for part in scene_parts(scene)]


def add_parts(spec: mujoco.MjSpec, parts: list[dict]) -> list[str]:
    """A free body per part (added after the arm: the arm's degrees of freedom stay the
    first six); returns their names."""
    names = []
    for part in parts:
        body = spec.worldbody.add_body()
        body.name = part["name"]
        body.pos = part["pos"]
        quat = np.zeros(4)
        mujoco.mju_euler2Quat(quat, np.asarray(part["euler"], float), "xyz")
        body.quat = quat
        free = body.add_freejoint()
        free.name = f"{part['name']}_free"
        geom = body.add_geom()
        geom.name = part["name"]
        geom.type = GEOM_TYPES[part["type"]]
        geom.size = part["size"] + [0.0] * (3 - len(part["size"]))
        geom.mass = part["mass"]
        geom.friction = [part["friction"], 0.005, 0.0001]
        geom.condim = 4
        geom.rgba = part["rgba"]
        names.append(part["name"])
    return names


class PartPoses:
    """Where the parts of ``m`` are (read from ``d`` in the physics thread or under its
    lock)."""

    def __init__(self, m: mujoco.MjModel, names: list[str]):
        self.names = list(names)
        self._bodies = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n) for n in names]

    def poses(self, d: mujoco.MjData) -> dict[str, np.ndarray]:
        """name → 4x4 pose (m, base frame)."""
        out = {}
        for name, b in zip(self.names, self._bodies):
            pose = np.eye(4)
            pose[:3, :3] = d.xmat[b].reshape(3, 3)
            pose[:3, 3] = d.xpos[b]
            out[name] = pose
        return out
