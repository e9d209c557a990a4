"""Collisions in the twin: contact geometry, a floor, an optional workcell, and the monitor
that turns a contact force above the collision level's threshold into a protective stop.

Levels (docs/interface.md, ``set_collisionlevel``): 0 off, 1–4 → 25/50/75/100 N of contact force
between the arm and the environment or itself.

Workcell files (``~scene``): YAML with a list of obstacles, each
``{name: table, type: box|sphere|cylinder|capsule, size: [...] (m, MuJoCo half-sizes),
pos: [x, y, z] (m, base frame), euler: [rx, ry, rz] (rad, optional), rgba: [...] (optional)}``
— or an MJCF file whose worldbody geoms are copied in.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable, Optional

import mujoco
import numpy as np

from .ft_sensor import TOOL_BODY

LEVEL_FORCE_N = {1: 25.0, 2: 50.0, 3: 75.0, 4: 100.0}
ARM_BODIES = [f"link_{i}" for i in range(1, 7)]
GEOM_TYPES = {"box": mujoco.mjtGeom.mjGEOM_BOX, "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
              "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
              "capsule": mujoco.mjtGeom.mjGEOM_CAPSULE}


# Contact bits (MuJoCo: two geoms touch when contype of one & conaffinity of the other ≠ 0).
# Everything keeps MuJoCo's default (contype 1, conaffinity 1) except the base mount and the two
# first links, which sit on it by construction: each has a contype bit of its own and
# conaffinity 1, so the mount and link_1/link_2 never meet, while each of them still meets the
# floor, every obstacle and part, and every other link.
BASE_MOUNT_CONTYPE = 2
FIRST_LINKS_CONTYPE = 4
FIRST_LINKS = ("link_1", "link_2")


def add_environment(spec: mujoco.MjSpec, scene: Optional[str]) -> None:
    """Floor at z = 0 (the base's mounting plane), scene obstacles, and the contacts the arm's
    own geometry must ignore: the base mount against link_1 and link_2 (contact bits above),
    neighbours along the chain, which touch by construction, and the wrist (link_4 … link_6),
    too compact for its cylinders not to overlap. The world body itself (floor, obstacles) is
    excluded against nothing: every link meets every obstacle."""
    for geom in _base_mount_geoms(spec.worldbody):      # before the floor is added
        geom.contype, geom.conaffinity = BASE_MOUNT_CONTYPE, 1
    for name in FIRST_LINKS:
        for geom in spec.body(name).geoms:
            geom.contype, geom.conaffinity = FIRST_LINKS_CONTYPE, 1
    floor = spec.worldbody.add_geom()
    floor.name = "floor"
    floor.type = mujoco.mjtGeom.mjGEOM_PLANE
    floor.size = [5.0, 5.0, 0.1]
    floor.rgba = [0.85, 0.85, 0.85, 1.0]
    if scene:
        _add_scene(spec, Path(scene))
    pairs = set(zip(ARM_BODIES, ARM_BODIES[1:]))
    pairs |= {("link_1", "link_3"), ("link_4", "link_6"), ("link_3", "link_5")}
    for a, b in sorted(pairs):
        exclude = spec.add_exclude()
        exclude.bodyname1, exclude.bodyname2 = a, b


def _base_mount_geoms(body) -> list:
    """The URDF's geometry below joint_1 (link_0 and base_link, fused into the world body when
    the model compiles): every geom of ``body`` and its children down to, not into, link_1."""
    geoms = list(body.geoms)
    for child in body.bodies:
        if child.name not in ARM_BODIES:
            geoms += _base_mount_geoms(child)
    return geoms


def _add_scene(spec: mujoco.MjSpec, path: Path) -> None:
    if not path.is_file():
        raise ValueError(f"scene file {path} does not exist")
    if path.suffix.lower() in (".xml", ".mjcf"):
        other = mujoco.MjSpec.from_file(str(path))
        for geom in other.worldbody.geoms:
            copy = spec.worldbody.add_geom()
            for attr in ("name", "type", "size", "pos", "quat", "rgba", "fromto"):
                try:
                    setattr(copy, attr, getattr(geom, attr))
                except (AttributeError, TypeError):
                    pass
        return
    import yaml
    data = yaml.safe_load(path.read_text()) or {}
    for i, item in enumerate(data.get("obstacles", [])):
        kind = item.get("type", "box")
        if kind not in GEOM_TYPES:
            raise ValueError(f"{path}: obstacle {i} has type {kind!r}, expected one of "
                             f"{', '.join(GEOM_TYPES)}")
        geom = spec.worldbody.add_geom()
        geom.name = str(item.get("name", f"obstacle_{i}"))
        geom.type = GEOM_TYPES[kind]
        size = list(item["size"]) + [0.0] * (3 - len(item["size"]))
        geom.size = size
        geom.pos = list(item.get("pos", [0, 0, 0]))
        if "euler" in item:
            quat = np.zeros(4)
            mujoco.mju_euler2Quat(quat, np.asarray(item["euler"], float), "xyz")
            geom.quat = quat
        geom.rgba = list(item.get("rgba", [0.6, 0.45, 0.3, 1.0]))


class CollisionMonitor:
    """Checks the contacts at the end of each 8 ms cycle (MuJoCo's contact list and contact
    forces of the cycle's last step); calls ``on_collision(message)`` once when an arm
    contact's normal force exceeds the threshold of the current level."""

    def __init__(self, m: mujoco.MjModel, on_collision: Callable[[str], None]):
        self._m = m
        self._on_collision = on_collision
        self.level = 2
        self.armed = True
        # the arm's links, and the tool side of a force/torque sensor when there is one
        arm = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)
               for name in ARM_BODIES + [TOOL_BODY]}
        self._arm_geoms = np.array([m.geom_bodyid[g] in arm for g in range(m.ngeom)])
        self._force = np.zeros(6)

    def check(self, d: mujoco.MjData) -> None:
        if d.ncon == 0 or self.level == 0 or not self.armed:
            return
        threshold = LEVEL_FORCE_N[self.level]
        for i in range(d.ncon):
            contact = d.contact[i]
            g1, g2 = contact.geom1, contact.geom2
            if not (self._arm_geoms[g1] or self._arm_geoms[g2]):
                continue
            mujoco.mj_contactForce(self._m, d, i, self._force)
            if self._force[0] > threshold:
                self.armed = False
                self._on_collision(f"collision: {self._name(g1)} touched {self._name(g2)} with "
                                   f"{self._force[0]:.0f} N (level {self.level}, threshold "
                                   f"{threshold:.0f} N)")
                return

    def _name(self, geom: int) -> str:
        m = self._m
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, geom)
        if name:
            return name
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, m.geom_bodyid[geom]) or f"geom {geom}"
