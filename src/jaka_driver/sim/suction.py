"""The twin's suction cup: a cup on the flange that holds a part whose face it touches while
its valve is open, switched by a tool digital output, its vacuum switch on a tool digital
input.

**Built** (:func:`add_suction_cup`): a body ``suction_cup`` on the tool body (the flange, or
the force/torque sensor's tool side) with a stem and a cup whose face is the grasp point
(site ``suction_grasp``), and one weld constraint per part of the scene, inactive.

**Held** (:class:`SuctionCup`, a tool-connector device): while tool DO ``valve`` is on and the
cup's face touches a part, that part's weld is switched on at the pose it has then (the weld's
relative pose is set to where the part is in the cup's frame): from then MuJoCo carries it with
the cup, its mass in every force the arm feels. The valve closed, the weld goes off and the
part falls. The vacuum switch (tool DI ``vacuum``) reads 1 while a part is held. Unpowered, the
valve does not open.

Units: m, kg, V; quaternions w x y z as MuJoCo's.
"""
from __future__ import annotations

from typing import Optional, Sequence

import mujoco
import numpy as np

from ..common.tool_shapes import SUCTION

BODY = "suction_cup"
CUP = "suction_cup_face"
GRASP_SITE = "suction_grasp"
MASS, STEM, CUP_SIZE = SUCTION.mass, SUCTION.stem, SUCTION.cup
_NEIGHBOURS = ("link_4", "link_5", "link_6")


def add_suction_cup(spec: mujoco.MjSpec, parent: str, parts: Sequence[str]) -> list[str]:
    """Add the cup on body ``parent`` and an inactive weld to each part; returns its body."""
    body = spec.body(parent).add_body()
    body.name = BODY
    stem = body.add_geom()
    stem.type = mujoco.mjtGeom.mjGEOM_CYLINDER
    stem.size = [STEM[0], STEM[1], 0.0]
    stem.pos = [0.0, 0.0, STEM[1]]
    stem.mass = MASS * 0.8
    stem.rgba = [0.3, 0.3, 0.32, 1.0]
    cup = body.add_geom()
    cup.name = CUP
    cup.type = mujoco.mjtGeom.mjGEOM_CYLINDER
    cup.size = [CUP_SIZE[0], CUP_SIZE[1], 0.0]
    cup.pos = [0.0, 0.0, 2 * STEM[1] + CUP_SIZE[1]]
    cup.mass = MASS * 0.2
    cup.rgba = [0.1, 0.1, 0.1, 1.0]
    site = body.add_site()
    site.name = GRASP_SITE
    site.pos = [0.0, 0.0, SUCTION.grasp_z]
    for part in parts:
        weld = spec.add_equality()
        weld.name = f"{BODY}_{part}"
        weld.type = mujoco.mjtEq.mjEQ_WELD
        weld.objtype = mujoco.mjtObj.mjOBJ_BODY
        weld.name1, weld.name2 = BODY, part
        weld.active = False
    for other in _NEIGHBOURS + (parent,):
        if other != BODY:
            exclude = spec.add_exclude()
            exclude.bodyname1, exclude.bodyname2 = other, BODY
    return [BODY]


class SuctionCup:
    """The cup of the twin ``m`` / ``d`` on the tool connector (see the module): ``valve`` the
    tool DO that opens it, ``vacuum`` the tool DI its switch drives (index 0 first)."""

    def __init__(self, m: mujoco.MjModel, d: mujoco.MjData, valve: int = 0, vacuum: int = 0):
        self._m, self._d = m, d
        self.valve, self.vacuum = valve, vacuum
        self._body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, BODY)
        self._cup = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, CUP)
        if self._body < 0 or self._cup < 0:
            raise ValueError("the twin's model has no suction cup (sim/suction.add_suction_cup)")
        # part geom → (weld id, part body)
        self._welds: dict[int, tuple[int, int]] = {}
        for e in range(m.neq):
            if m.eq_type[e] == mujoco.mjtEq.mjEQ_WELD and m.eq_obj1id[e] == self._body:
                part = int(m.eq_obj2id[e])
                for g in range(m.ngeom):
                    if m.geom_bodyid[g] == part:
                        self._welds[g] = (e, part)
        self.volts = 0.0
        self.reset()

    def reset(self) -> None:
        """Valve closed, nothing held (the supply stays as it is)."""
        self.open = False
        self.held: Optional[int] = None          # the weld holding a part
        self._d.eq_active[:] = self._m.eq_active0

    @property
    def powered(self) -> bool:
        return self.volts > 0.0

    def held_part(self) -> Optional[str]:
        if self.held is None:
            return None
        return mujoco.mj_id2name(self._m, mujoco.mjtObj.mjOBJ_BODY,
                                 int(self._m.eq_obj2id[self.held]))

    # ---- ToolDevice ---------------------------------------------------------------------
    def power(self, volts: float) -> None:
        self.volts = float(volts)
        if not self.powered:
            self._release()

    def rs485(self, channel: int, frame: bytes, baudrate: int) -> None:
        """A suction cup has no RS485 line."""

    def read_register(self, channel: int, sig_type: int, address: int) -> Optional[int]:
        return None

    def tool_outputs(self, levels: Sequence[float]) -> None:
        self.open = len(levels) > self.valve and levels[self.valve] >= 0.5
        if not self.open:
            self._release()

    def tool_inputs(self) -> dict[int, float]:
        return {self.vacuum: 1.0 if self.held is not None else 0.0}

    def on_cycle(self) -> None:
        """With the valve open and powered, take the first part whose geom the cup's face
        touches."""
        if not (self.open and self.powered) or self.held is not None:
            return
        d = self._d
        for i in range(d.ncon):
            c = d.contact[i]
            other = c.geom2 if c.geom1 == self._cup else c.geom1 if c.geom2 == self._cup else -1
            if other in self._welds:
                self._hold(*self._welds[other])
                return

    def _hold(self, weld: int, part: int) -> None:
        """Switch ``weld`` on with the part where it is now, in the cup's frame."""
        d, m = self._d, self._m
        cup_pos, cup_quat = d.xpos[self._body], d.xquat[self._body]
        inverse = np.zeros(4)
        mujoco.mju_negQuat(inverse, cup_quat)
        rel_pos = np.zeros(3)
        mujoco.mju_rotVecQuat(rel_pos, d.xpos[part] - cup_pos, inverse)
        rel_quat = np.zeros(4)
        mujoco.mju_mulQuat(rel_quat, inverse, d.xquat[part])
        m.eq_data[weld, 0:3] = 0.0            # anchor at the part's origin
        m.eq_data[weld, 3:6] = rel_pos
        m.eq_data[weld, 6:10] = rel_quat
        m.eq_data[weld, 10] = 1.0             # torque scale
        d.eq_active[weld] = 1
        self.held = weld

    def _release(self) -> None:
        if self.held is not None:
            self._d.eq_active[self.held] = 0
            self.held = None
