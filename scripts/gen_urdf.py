#!/usr/bin/env python3
"""Generate ``urdf/jaka_<model>.urdf`` and ``config/<model>.yaml`` for the 22 six-axis JAKA arms.

The joint chains (origins, axes, position and velocity limits, base offset) are JAKA's, copied
number for number in ``arm_catalogue.py`` (with its documented deviations), so that joint zero,
joint directions and the flange frame equal the controller's. Everything else follows the rules
below, stated once here and in docs/models.md:

* **mass** (:func:`arm_mass`): the catalogue weight where one is known (Zu 3/5/7/12/18), else
  ``MASS_FIT``: a power law in the rated payload and the arm length (upper arm + forearm), fitted
  to those five weights; spread over the links by ``MASS_SHARE`` as solid cylinders
  (:mod:`arm_geometry`). JAKA's URDF masses (mesh volume × a default density) are not used.
* **joint accelerations** (:func:`joint_accelerations`): by payload class, within JAKA's
  recommended 720 °/s² for joint moves.
* **TCP acceleration** (:func:`tcp_acceleration`): 8000 mm/s² (libjaka's bound), 6000 from 12 kg
  payload up, the MiniCobo's 4000 (libjaka).
* **joint torque limits** (:func:`torque_limits`): ``TORQUE_MARGIN`` × the torque the model's own
  twin needs to hold its rated payload anywhere in its workspace while all joints accelerate at
  their limits (JAKA's URDF efforts are placeholders).

Frames: ``base_link`` (root, the mounting face) → fixed offset → ``link_0`` → ``joint_1`` …
``joint_6`` → ``link_6`` → ``flange`` (identity) → ``tool0`` (identity).

Usage: ``scripts/gen_urdf.py [ROOT]`` (default: the repository): writes ``ROOT/urdf`` and
``ROOT/config``. Deterministic; the generated files are committed, this script is their source.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "src"))   # jaka_driver
from arm_catalogue import ARMS, MODEL_NAMES, Arm  # noqa: E402
from arm_geometry import link_frames, link_geometry, link_inertial  # noqa: E402
from jaka_driver.common.transforms import rotvec_to_matrix, rpy_to_matrix  # noqa: E402

__all__ = ["MODEL_NAMES", "render", "render_config", "main"]

# Share of the arm's mass per link_0..link_6: heavy shoulder and upper arm, light wrist.
MASS_SHARE = (0.13, 0.17, 0.31, 0.17, 0.09, 0.09, 0.04)
# mass (kg) = k · payload(kg)^a · length(m)^b, least squares in log over the five catalogue
# weights (zu3 12, zu5 23, zu7 22, zu12 41, zu18 35 kg; residuals within 5 %).
MASS_FIT = (19.2327, 0.246120, 0.964516)
TORQUE_MARGIN = 1.1
PAYLOAD_OFFSET = 0.1    # m along the flange z: where the rated payload sits for the torque rule
SERVO_KP, SERVO_KD = 22500, 300   # 1/s², 1/s: ωn = 150 rad/s, ζ = 1 (sim/servo.py)
IO = {"cabinet": {"digital_in": 16, "digital_out": 16, "analog_in": 2, "analog_out": 2},
      "tool": {"digital_in": 2, "digital_out": 2, "analog_in": 2, "analog_out": 0},
      "extension": {"digital_in": 8, "digital_out": 8, "analog_in": 4, "analog_out": 4}}

ARM_RGBA = "0.92 0.92 0.90 1"  # light grey/white covers
JOINT_RGBA = "0.22 0.23 0.25 1"  # dark joint modules


def arm_length(arm: Arm) -> float:
    """Upper arm + forearm (m): distance J2 → J3 axis plus J3 axis → wrist, at q = 0."""
    frames = link_frames(arm)[1:]
    o = [T[:3, 3] for T in frames]
    u = [T[:3, :3] @ np.asarray(r.axis) for T, r in zip(frames, arm.joints)]
    upper = o[2] - o[1]
    fore = o[3] - o[2]          # J4's origin is the wrist in every JAKA file
    # lengths across the parallel J2/J3 axes: drop the components along them
    return float(np.linalg.norm(upper - (upper @ u[1]) * u[1])
                 + np.linalg.norm(fore - (fore @ u[2]) * u[2]))


def arm_mass(arm: Arm) -> tuple[float, str]:
    """(mass kg, where it comes from): the catalogue weight, else the ``MASS_FIT`` rule."""
    if arm.catalogue_mass_kg is not None:
        return arm.catalogue_mass_kg, arm.mass_source
    k, a, b = MASS_FIT
    mass = round(k * arm.payload_kg ** a * arm_length(arm) ** b, 1)
    return mass, "mass rule (payload and arm length, fitted to the Zu catalogue weights)"


def joint_accelerations(arm: Arm) -> tuple[float, ...]:
    """rad/s², J1…J6: 720 °/s² for arms up to 3 kg; 600 °/s² on J1–J3 and 720 on the wrist up
    to 7 kg; 360 / 600 °/s² from 12 kg up (the heavier the arm, the gentler its big joints)."""
    if arm.payload_kg <= 3:
        return (12.57,) * 6
    if arm.payload_kg <= 7:
        return (10.47,) * 3 + (12.57,) * 3
    return (6.28,) * 3 + (10.47,) * 3


def tcp_acceleration(arm: Arm) -> float:
    """mm/s²: libjaka's Cartesian bound (8000; the MiniCobo's 4000), 6000 from 12 kg up."""
    if arm.name == "minicobo":
        return 4000.0
    return 8000.0 if arm.payload_kg <= 7 else 6000.0


def torque_limits(arm: Arm) -> tuple[float, ...]:
    """N·m, J1…J6 (see the module docstring). Each joint needs, at worst over 2000
    configurations inside the limits, |gravity torque| + Σ_k |M_jk| · a_k: holding the rated
    payload (``PAYLOAD_OFFSET`` out along the flange z) while every joint accelerates at its
    limit in the direction that loads this one most (a joint move accelerates all joints at
    once, and the big joints' acceleration loads the wrist). J1–J3 are one module size and
    J4–J6 another, as on the real arms: each group's limit is ``TORQUE_MARGIN`` × its largest
    need (the margin for the velocity terms the need leaves out), rounded up to 5 N·m (1 N·m
    below 50)."""
    import pinocchio as pin
    model = pin.buildModelFromXML(render(arm.name, effort=(1.0,) * 6))
    frame = model.frames[model.getFrameId("flange")]
    placement = frame.placement * pin.SE3(np.eye(3), np.array([0.0, 0.0, PAYLOAD_OFFSET]))
    model.appendBodyToJoint(frame.parentJoint,
                            pin.Inertia.FromSphere(arm.payload_kg, 0.01), placement)
    data = model.createData()
    lo = np.array([r.lower for r in arm.joints])
    hi = np.array([r.upper for r in arm.joints])
    accel = np.array(joint_accelerations(arm))
    need = np.zeros(6)
    for q in np.random.default_rng(25).uniform(lo, hi, (2000, 6)):
        g = pin.computeGeneralizedGravity(model, data, q)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T        # crba fills the upper triangle
        need = np.maximum(need, np.abs(g) + np.abs(M) @ accel)
    out = []
    for group in (need[:3], need[3:]):
        limit = TORQUE_MARGIN * float(group.max())
        step = 1.0 if limit < 50.0 else 5.0
        out += [float(np.ceil(limit / step) * step)] * 3
    return tuple(out)


def _f(x: float) -> str:
    """Shortest exact-enough text of a float (9 significant digits; tiny and -0 → 0)."""
    if abs(x) < 1e-12:
        return "0"
    s = f"{float(x):.9g}"
    return "0" if s in ("-0", "0") else s


def _v(xs) -> str:
    return " ".join(_f(x) for x in xs)


def render(name: str, effort=None) -> str:
    """The URDF text of model ``name``; ``effort`` (N·m, J1…J6) defaults to
    :func:`torque_limits`."""
    arm = ARMS[name]
    effort = torque_limits(arm) if effort is None else effort
    mass, _ = arm_mass(arm)
    geometry = link_geometry(arm)
    out = [
        '<?xml version="1.0"?>',
        "<!-- GENERATED by scripts/gen_urdf.py - edit the generator, not this file.",
        f"     {arm.title}: JAKA's joint chain (jaka_description), our own geometry,",
        f"     masses (total {mass:g} kg) and effort limits. Units: m, rad, kg, N·m. -->",
        f'<robot name="jaka_{name}">',
        f'  <material name="arm_white"><color rgba="{ARM_RGBA}"/></material>',
        f'  <material name="joint_dark"><color rgba="{JOINT_RGBA}"/></material>',
        '  <link name="base_link"/>',
        '  <joint name="base_link-link_0" type="fixed">',
        '    <parent link="base_link"/>',
        '    <child link="link_0"/>',
        f'    <origin xyz="{_v(arm.mount)}" rpy="0 0 0"/>',
        "  </joint>",
    ]
    for i, cyls in enumerate(geometry):
        link_mass = mass * MASS_SHARE[i]
        com, inertia = link_inertial(cyls, link_mass)
        out += [f'  <link name="link_{i}">',
                "    <inertial>",
                f'      <origin xyz="{_v(com)}" rpy="0 0 0"/>',
                f'      <mass value="{_f(link_mass)}"/>',
                f'      <inertia ixx="{_f(inertia[0, 0])}" ixy="{_f(inertia[0, 1])}" '
                f'ixz="{_f(inertia[0, 2])}" iyy="{_f(inertia[1, 1])}" iyz="{_f(inertia[1, 2])}" '
                f'izz="{_f(inertia[2, 2])}"/>',
                "    </inertial>"]
        for tag in ("visual", "collision"):
            for c in cyls:
                out += [f"    <{tag}>",
                        f'      <origin xyz="{_v(c.centre)}" rpy="{_v(c.rpy)}"/>',
                        f'      <geometry><cylinder radius="{_f(c.radius)}" '
                        f'length="{_f(c.length)}"/></geometry>']
                if tag == "visual":
                    out.append(f'      <material name="'
                               f'{"arm_white" if c.material == "arm" else "joint_dark"}"/>')
                out.append(f"    </{tag}>")
        out.append("  </link>")
        if i < 6:
            row = arm.joints[i]
            out += [f'  <joint name="joint_{i + 1}" type="revolute">',
                    f'    <parent link="link_{i}"/>',
                    f'    <child link="link_{i + 1}"/>',
                    f'    <origin xyz="{_v(row.xyz)}" rpy="{_v(row.rpy)}"/>',
                    f'    <axis xyz="{_v(row.axis)}"/>',
                    f'    <limit lower="{_f(row.lower)}" upper="{_f(row.upper)}" '
                    f'effort="{_f(effort[i])}" velocity="{_f(row.velocity)}"/>',
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


def flange_positions(arm: Arm, qs: np.ndarray) -> np.ndarray:
    """Flange positions (N, 3), m, base frame, at joint positions ``qs`` (N, 6) rad."""
    n = len(qs)
    R = np.broadcast_to(np.eye(3), (n, 3, 3))
    p = np.broadcast_to(np.asarray(arm.mount, float), (n, 3))
    for row, q in zip(arm.joints, qs.T):
        p = p + R @ np.asarray(row.xyz)
        k = np.asarray(row.axis) / np.linalg.norm(row.axis)
        R = R @ rpy_to_matrix(*row.rpy) @ rotvec_to_matrix(q[:, None] * k)
    return p


def reach(arm: Arm) -> float:
    """m: the farthest the flange centre gets from the shoulder (the J1 axis at the height of
    J2): the farthest of 20 000 configurations inside the limits, refined by a coordinate
    search from the five farthest."""
    shoulder = link_frames(arm)[2][:3, 3]
    lo = np.array([r.lower for r in arm.joints])
    hi = np.array([r.upper for r in arm.joints])

    def dist(qs):
        return np.linalg.norm(flange_positions(arm, qs) - shoulder, axis=1)

    qs = np.random.default_rng(7).uniform(lo, hi, (20000, 6))
    top = 0.0
    for q in qs[np.argsort(dist(qs))[-5:]]:
        d, step = float(dist(q[None])[0]), 0.2
        while step > 1e-4:
            moves = np.repeat(q[None], 12, axis=0)
            for j in range(6):
                moves[2 * j, j] += step
                moves[2 * j + 1, j] -= step
            moves = np.clip(moves, lo, hi)
            dm = dist(moves)
            if dm.max() > d:
                q, d = moves[int(np.argmax(dm))], float(dm.max())
            else:
                step /= 2
        top = max(top, d)
    return top


def sensor_range_of(arm: Arm) -> tuple[float, ...]:
    """A flange sensor's range for ``arm`` (N, N·m): 1.5 g on the rated payload, at least
    200 N, rounded up to 50 N; moments that force at a 50 mm lever."""
    force = max(200.0, 50.0 * np.ceil(1.5 * 9.81 * arm.payload_kg / 50.0))
    return (force,) * 3 + (force * 0.05,) * 3


def render_config(name: str) -> str:
    """The text of ``config/<name>.yaml``: what the URDF cannot say."""
    arm = ARMS[name]
    mass, mass_source = arm_mass(arm)
    acc = joint_accelerations(arm)
    deg = [round(np.degrees(a)) for a in acc]
    payload_note = "; the MiniCobo's is an assumption" if name == "minicobo" else ""
    home_note = "; for the A12 J4 and J5 at 0 (JAKA's is singular)" if name == "a12" else ""
    sensor_range = sensor_range_of(arm)
    io = "\n".join(f"  {k + ':':<10} {{{', '.join(f'{s}: {n}' for s, n in v.items())}}}"
                   for k, v in IO.items())
    return f"""\
# {arm.title}: per-model data that is NOT in urdf/jaka_{name}.urdf.
# GENERATED by scripts/gen_urdf.py from scripts/arm_catalogue.py - edit those, not this file.
# The URDF is the single source of truth for joint names, position/velocity/effort limits,
# kinematics and masses; jaka_driver.common.load_model("{name}") merges both.
model: {name}
title: {arm.title}
# Kinematic layout (docs/models.md, "Three kinematic structures"): zu, forearm_roll or
# spherical_wrist.
structure: {arm.structure}

# Rated payload, kg (JAKA's naming: the model number is the payload{payload_note}).
rated_payload_kg: {arm.payload_kg:g}

# Arm mass in the URDF, kg: {mass_source}.
arm_mass_kg: {mass:g}

# Reach, mm: the farthest the flange centre gets from the shoulder (computed from the chain).
reach_mm: {reach(arm) * 1000:.0f}

# Where the twin starts, deg: JAKA's named pose "pose_1" (MoveIt SRDF){home_note}.
home_deg: [{", ".join(f"{x:g}" for x in arm.home)}]

# Maximum joint accelerations, rad/s^2, J1..J6 ({deg[0]} deg/s^2 on J1-J3, {deg[3]} deg/s^2 on
# the wrist).
# JAKA publishes none; JAKA recommends <= 720 deg/s^2 (12.57 rad/s^2) for MoveJ.
max_joint_acceleration_rad_s2: [{", ".join(f"{a:g}" for a in acc)}]

# Cartesian bounds of the TCP: speed, mm/s, {arm.tcp_speed_source};
# acceleration, mm/s^2, the rule of scripts/gen_urdf.py.
max_tcp_speed_mm_s: {arm.tcp_speed_mm_s:g}
max_tcp_accel_mm_s2: {tcp_acceleration(arm):g}

# Joint position servo of the MuJoCo twin, J1..J6 (jaka_driver/sim/servo.py): MuJoCo position
# actuators following the interpolated setpoint, with inertia, velocity and Coriolis
# feed-forward and gravity compensation; the gains are accelerations, kp = wn^2 in 1/s^2,
# kd = 2*zeta*wn in 1/s (wn = 150 rad/s, 24 Hz; zeta = 1), scaled each cycle by the joint's
# inertia at the current pose.
servo:
  kp: [{", ".join([str(SERVO_KP)] * 6)}]
  kd: [{", ".join([str(SERVO_KD)] * 6)}]

# IO channel counts, addressed like jaka_msgs/SetIO and GetIO:
#   type 0 = cabinet (IO_CABINET), 1 = tool (IO_TOOL), 2 = extension (IO_EXTEND);
#   path 0 = input, 1 = output (GetIO); SetIO always addresses outputs.
# Indices run 0..count-1. The controller reports larger arrays (din/dout 144+) that include
# bus and function IO; these are the physical channels of a standard cabinet and tool.
io:
{io}

# Flange force/torque sensor (docs/interface.md, "Force"): whether this arm carries one (the
# node parameter ~force_sensor overrides it), the largest reading per axis (Fx Fy Fz N,
# Mx My Mz N·m, sensor frame = flange), and what the twin adds: the offset of an unzeroed
# sensor, the noise of each sample (standard deviation), and the tool under the sensor, a
# capsule along flange z (length to its tip's centre, radius) that touches what it presses on.
force_sensor:
  mounted: false
  range: [{", ".join(f"{x:g}" for x in sensor_range)}]
  bias: [1.2, -0.8, 2.5, 0.04, -0.03, 0.02]
  noise: [0.05, 0.05, 0.05, 0.002, 0.002, 0.002]
  probe: {{length_mm: 100, radius_mm: 10}}
"""


def main(argv: list[str]) -> int:
    root = Path(argv[1]) if len(argv) > 1 else Path(__file__).resolve().parent.parent
    for sub in ("urdf", "config"):
        (root / sub).mkdir(parents=True, exist_ok=True)
    for name in MODEL_NAMES:
        for path, text in ((root / "urdf" / f"jaka_{name}.urdf", render(name)),
                           (root / "config" / f"{name}.yaml", render_config(name))):
            path.write_text(text)
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
