#!/usr/bin/env python3
"""Generate ``urdf/jaka_<model>.urdf`` for the JAKA Zu 3/5/7/12/18.

The joint chains (origins, axes, position and velocity limits, fixed base offset) are JAKA's
official ``jaka_description`` values (docs/models.md, "Kinematic chains"), copied number for number
so that joint zero, joint directions and the flange frame equal the controller's. Everything else
is ours: simple cylinders for geometry, masses that add up to the catalogue weight (the official
Zu3/5/7 URDF masses are ~4x too heavy), inertias of those cylinders, and realistic effort limits
(the official ones are placeholders).

Frames: ``base_link`` (root, robot mounting face) → fixed offset → ``link_0`` → ``joint_1`` …
``joint_6`` → ``link_6`` → ``flange`` (identity) → ``tool0`` (identity).

Usage: ``scripts/gen_urdf.py [OUT_DIR]`` (default ``urdf/`` next to this script). The output is
deterministic; the generated files are committed, this script is their source.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MODEL_NAMES = ("zu3", "zu5", "zu7", "zu12", "zu18")


@dataclass(frozen=True)
class JointRow:
    """One revolute joint of the official chain: origin in the parent link frame (m, rad)."""

    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    lower: float
    upper: float
    velocity: float


@dataclass(frozen=True)
class ArmSpec:
    """Per-model data: the official chain plus our geometry/mass choices."""

    base_xyz: tuple[float, float, float]  # world→Link_0 fixed offset of the official URDF
    joints: tuple[JointRow, ...]
    total_mass_kg: float  # catalogue weight of the arm
    effort_nm: tuple[float, ...]  # rated joint torques we assume, N·m
    r_arm: float  # upper-arm tube radius, m; the other radii derive from it
    r_wrist: float  # wrist drum radius, m


# Official limits shared by every Zu model (docs/models.md, "Joint position limits"):
# J2/J4 −85°…265°, J3 ±175°.
_LIM = ((-6.28, 6.28), (-1.48, 4.62), (-3.05, 3.05), (-1.48, 4.62), (-6.28, 6.28), (-6.28, 6.28))
_RX = (1.5708, 0.0, 0.0)  # as written in the official URDFs (not exactly pi/2)
_RXN = (-1.5708, 0.0, 0.0)
_R0 = (0.0, 0.0, 0.0)


def _chain(d1, a2, a3, j4xyz, d5, d6, vel) -> tuple[JointRow, ...]:
    origins = (((0, 0, d1), _R0), ((0, 0, 0), _RX), ((a2, 0, 0), _R0),
               (j4xyz, _R0), ((0, -d5, 0), _RX), ((0, d6, 0), _RXN))
    return tuple(JointRow(tuple(float(v) for v in xyz), rpy, lo, hi, v)
                 for (xyz, rpy), (lo, hi), v in zip(origins, _LIM, vel))


SPECS: dict[str, ArmSpec] = {
    "zu3": ArmSpec((-0.002, 0.0, -0.00001),
                   _chain(0.15055, 0.248, 0.228, (0.228, 1.1925e-5, -0.115), 0.1175, 0.1065,
                          (3.14, 3.14, 3.14, 3.84, 3.84, 3.84)),
                   12.0, (80, 80, 80, 15, 15, 15), 0.045, 0.040),
    "zu5": ArmSpec((0.0, 0.0, 0.0),
                   _chain(0.12015, 0.43, 0.3685, (0.3685, -1.185e-5, -0.114), 0.1135, 0.107,
                          (3.14,) * 6),
                   23.0, (150, 150, 150, 28, 28, 28), 0.060, 0.045),
    "zu7": ArmSpec((0.0, 0.0, 0.0),
                   _chain(0.12015, 0.36, 0.30353, (0.30353, 0.0, -0.11501), 0.1135, 0.107,
                          (3.14,) * 6),
                   22.0, (150, 150, 150, 28, 28, 28), 0.060, 0.045),
    "zu12": ArmSpec((0.0, 0.0, 0.04),
                    _chain(0.10265, 0.595, 0.5715, (0.5715, 0.0, -0.1315), 0.115, 0.1035,
                           (2.09, 2.09, 2.09, 3.14, 3.14, 3.14)),
                    41.0, (330, 330, 330, 54, 54, 54), 0.075, 0.050),
    "zu18": ArmSpec((0.0, 0.0, 0.0),
                    _chain(0.14265, 0.51, 0.4, (0.4, 0.0, -0.154), 0.115, 0.1035,
                           (2.09, 2.09, 3.14, 3.14, 3.14, 3.14)),
                    35.0, (380, 380, 380, 54, 54, 54), 0.075, 0.050),
}

# Share of the total mass per link_0..link_6: heavy shoulder and upper arm, light wrist.
MASS_SHARE = (0.13, 0.17, 0.31, 0.17, 0.09, 0.09, 0.04)

ARM_RGBA = "0.92 0.92 0.90 1"  # light grey/white covers
JOINT_RGBA = "0.22 0.23 0.25 1"  # dark joint modules


@dataclass(frozen=True)
class Cylinder:
    """A solid cylinder in a link frame: centre (m), unit axis, radius, length, material."""

    centre: tuple[float, float, float]
    axis: str  # "x", "y" or "z" of the link frame
    radius: float
    length: float
    material: str  # "arm" or "joint"

    @property
    def volume(self) -> float:
        return np.pi * self.radius ** 2 * self.length

    @property
    def rpy(self) -> tuple[float, float, float]:
        # URDF cylinders lie along their own z; turn z onto the wanted link axis.
        return {"x": (0.0, np.pi / 2, 0.0), "y": (-np.pi / 2, 0.0, 0.0), "z": (0.0, 0.0, 0.0)}[self.axis]

    def inertia_about_centre(self, mass: float) -> np.ndarray:
        """Inertia tensor (kg·m²) about the centre, in link-frame axes."""
        r, h = self.radius, self.length
        axial = 0.5 * mass * r * r
        radial = mass * (3 * r * r + h * h) / 12.0
        k = "xyz".index(self.axis)
        diag = np.full(3, radial)
        diag[k] = axial
        return np.diag(diag)


def _segment(a: float, b: float, axis: str, radius: float, material: str,
             at: tuple[float, float] = (0.0, 0.0)) -> Cylinder:
    """Cylinder along ``axis`` from coordinate ``a`` to ``b``; ``at`` = the other two coords."""
    k = "xyz".index(axis)
    centre = [0.0, 0.0, 0.0]
    others = [i for i in range(3) if i != k]
    centre[others[0]], centre[others[1]] = at
    centre[k] = 0.5 * (a + b)
    return Cylinder(tuple(centre), axis, radius, abs(b - a), material)


def link_geometry(spec: ArmSpec) -> list[list[Cylinder]]:
    """Cylinders of link_0..link_6, each in its own link frame (z = the link's joint axis)."""
    j = spec.joints
    d1 = j[0].xyz[2]
    a2 = j[2].xyz[0]
    a3, _, zoff4 = j[3].xyz  # forearm length and the elbow's lateral offset (negative)
    d5 = -j[4].xyz[1]
    d6 = j[5].xyz[1]
    ra, rw = spec.r_arm, spec.r_wrist
    rj = 1.1 * ra  # shoulder/elbow joint modules are a little wider than the tubes
    rf = 0.85 * ra  # forearm tube
    base_z0 = -spec.base_xyz[2]  # the base reaches down to the mounting face (base_link z=0)
    base_top = max(d1 - rj, base_z0 + 0.03)
    flange_t = 0.012  # flange disc thickness
    return [
        # link_0: base column from the mounting face up to just below the shoulder module.
        [_segment(base_z0, base_top, "z", 1.15 * ra, "arm")],
        # link_1: joint-1 module (vertical drum) at the shoulder.
        [_segment(-rj, rj, "z", rj, "joint")],
        # link_2: joint-2 module on its axis + upper-arm tube along x to the elbow module.
        [_segment(-rj, rj, "z", rj, "joint"),
         _segment(rj, a2 - rj, "x", ra, "arm")],
        # link_3: joint-3 module spanning the elbow offset + forearm tube in line with wrist 1.
        [_segment(zoff4 - rf, rj, "z", rj, "joint"),
         _segment(rj, a3 - rw, "x", rf, "arm", at=(0.0, zoff4))],
        # link_4: wrist-1 module + the short tube down to wrist 2.
        [_segment(-rw, rw, "z", rw, "joint"),
         _segment(-(d5 - rw), -rw, "y", 0.9 * rw, "arm")],
        # link_5: wrist-2 module + the joint-6 module reaching to the flange.
        [_segment(-rw, rw, "z", rw, "joint"),
         _segment(rw, d6 - flange_t, "y", rw, "arm")],
        # link_6: the flange disc, its outer face is the flange frame (z = 0).
        [_segment(-flange_t, 0.0, "z", 0.7 * rw, "joint")],
    ]


def link_inertial(cyls: list[Cylinder], mass: float) -> tuple[np.ndarray, np.ndarray]:
    """COM (m) and inertia about it (kg·m², link axes) of solid cylinders of one density."""
    vols = np.array([c.volume for c in cyls])
    masses = mass * vols / vols.sum()
    centres = np.array([c.centre for c in cyls])
    com = masses @ centres / mass
    inertia = np.zeros((3, 3))
    for c, m, p in zip(cyls, masses, centres):
        d = p - com
        inertia += c.inertia_about_centre(m) + m * (d @ d * np.eye(3) - np.outer(d, d))
    return com, inertia


def _f(x: float) -> str:
    """Shortest exact-enough text of a float (9 significant digits; -0 → 0)."""
    s = f"{float(x):.9g}"
    return "0" if s in ("-0", "0") else s


def _v(xs) -> str:
    return " ".join(_f(x) for x in xs)


def render(name: str) -> str:
    spec = SPECS[name]
    geometry = link_geometry(spec)
    out = [
        '<?xml version="1.0"?>',
        f"<!-- GENERATED by scripts/gen_urdf.py - edit the generator, not this file.",
        f"     JAKA {name.upper()}: official joint chain (jaka_description), our own geometry,",
        f"     masses (total {spec.total_mass_kg:g} kg) and effort limits. Units: m, rad, kg, N·m. -->",
        f'<robot name="jaka_{name}">',
        f'  <material name="arm_white"><color rgba="{ARM_RGBA}"/></material>',
        f'  <material name="joint_dark"><color rgba="{JOINT_RGBA}"/></material>',
        '  <link name="base_link"/>',
        '  <joint name="base_link-link_0" type="fixed">',
        '    <parent link="base_link"/>',
        '    <child link="link_0"/>',
        f'    <origin xyz="{_v(spec.base_xyz)}" rpy="0 0 0"/>',
        "  </joint>",
    ]
    for i, cyls in enumerate(geometry):
        mass = spec.total_mass_kg * MASS_SHARE[i]
        com, inertia = link_inertial(cyls, mass)
        out += [f'  <link name="link_{i}">',
                "    <inertial>",
                f'      <origin xyz="{_v(com)}" rpy="0 0 0"/>',
                f'      <mass value="{_f(mass)}"/>',
                f'      <inertia ixx="{_f(inertia[0, 0])}" ixy="{_f(inertia[0, 1])}" '
                f'ixz="{_f(inertia[0, 2])}" iyy="{_f(inertia[1, 1])}" iyz="{_f(inertia[1, 2])}" '
                f'izz="{_f(inertia[2, 2])}"/>',
                "    </inertial>"]
        for tag in ("visual", "collision"):
            for c in cyls:
                out += [f"    <{tag}>",
                        f'      <origin xyz="{_v(c.centre)}" rpy="{_v(c.rpy)}"/>',
                        f'      <geometry><cylinder radius="{_f(c.radius)}" length="{_f(c.length)}"/></geometry>']
                if tag == "visual":
                    out.append(f'      <material name="{"arm_white" if c.material == "arm" else "joint_dark"}"/>')
                out.append(f"    </{tag}>")
        out.append("  </link>")
        if i < 6:
            row = spec.joints[i]
            out += [f'  <joint name="joint_{i + 1}" type="revolute">',
                    f'    <parent link="link_{i}"/>',
                    f'    <child link="link_{i + 1}"/>',
                    f'    <origin xyz="{_v(row.xyz)}" rpy="{_v(row.rpy)}"/>',
                    '    <axis xyz="0 0 1"/>',
                    f'    <limit lower="{_f(row.lower)}" upper="{_f(row.upper)}" '
                    f'effort="{_f(spec.effort_nm[i])}" velocity="{_f(row.velocity)}"/>',
                    "  </joint>"]
    for parent, child in (("link_6", "flange"), ("flange", "tool0")):
        out += [f'  <joint name="{parent}-{child}" type="fixed">',
                f'    <parent link="{parent}"/>',
                f'    <child link="{child}"/>',
                '    <origin xyz="0 0 0" rpy="0 0 0"/>',
                "  </joint>",
                f'  <link name="{child}"/>']
    out.append("</robot>")
    return "\n".join(out) + "\n"


def main(argv: list[str]) -> int:
    out_dir = Path(argv[1]) if len(argv) > 1 else Path(__file__).resolve().parent.parent / "urdf"
    out_dir.mkdir(parents=True, exist_ok=True)
    for name in MODEL_NAMES:
        path = out_dir / f"jaka_{name}.urdf"
        path.write_text(render(name))
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
