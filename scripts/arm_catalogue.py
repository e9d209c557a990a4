"""The 22 six-axis JAKA arms as JAKA's own files describe them, plus the numbers JAKA does not give.

Source of every joint row: JAKA's public ROS 2 description package, ``JAKARobotics/jaka_ros2`` at
commit c83b594 (2026-03-02), ``src/jaka_description/urdf/jaka_<model>.urdf`` — the joint origins
(xyz m, rpy rad), axes, position limits (rad) and velocity limits (rad/s) copied number for
number, as written (π/2 is written 1.5708 there, and so it is here). JAKA's ROS 1 package
(``JakaCobot/jaka_robot`` v2.2) has the same numbers for the 15 models it ships, except where
``DEVIATIONS`` says otherwise. Where a file is broken or two sources disagree, the choice made
here is in ``DEVIATIONS`` (and docs/models.md, "Where JAKA's files are not used as written").

JAKA's files carry no usable masses (CAD mesh volume × a default density: a Zu 5 of 96 kg for a
23 kg arm), no acceleration limits and placeholder efforts; those come from the rules in
``gen_urdf.py`` and the catalogue facts below (each with its source).

Units: m, rad, rad/s, kg; Cartesian speeds in mm/s as JAKA states them.
"""
from __future__ import annotations

from dataclasses import dataclass

# JAKA writes π/2 as 1.5708 and π as 3.1416.
H = 1.5708
PI = 3.1416


@dataclass(frozen=True)
class Row:
    """One revolute joint as JAKA's URDF writes it: origin in the parent link (m, rad), axis in
    the joint frame, position limits (rad), velocity limit (rad/s)."""

    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    axis: tuple[float, float, float]
    lower: float
    upper: float
    velocity: float


@dataclass(frozen=True)
class Arm:
    """One model: JAKA's chain and the catalogue facts this project uses.

    ``mount``: JAKA's ``world`` → base link fixed offset (xyz m), the driver's ``base_link`` →
    ``link_0``. ``tcp_speed_mm_s`` and its ``tcp_speed_source``; ``catalogue_mass_kg`` is None
    where no catalogue weight is known (the mass rule of ``gen_urdf.py`` decides then);
    ``home``: JAKA's named state ``pose_1`` (MoveIt SRDF), deg (the A12: see DEVIATIONS).
    ``structure`` names the kinematic layout (docs/models.md, "Three kinematic structures")."""

    name: str
    title: str
    mount: tuple[float, float, float]
    joints: tuple[Row, ...]
    payload_kg: float
    tcp_speed_mm_s: float
    tcp_speed_source: str
    structure: str
    home: tuple[float, ...]
    catalogue_mass_kg: float | None = None
    mass_source: str = ""


_STD = ((-6.28, 6.28), (-1.48, 4.62), (-3.05, 3.05), (-1.48, 4.62), (-6.28, 6.28), (-6.28, 6.28))
_Z = (0.0, 0.0, 1.0)
_R0 = (0.0, 0.0, 0.0)
_POSE_1 = (0.0, 90.0, -90.0, 90.0, 90.0, 0.0)   # deg; JAKA's SRDF writes 1.5707 rad
_LIBJAKA = "libjaka crate (Cartesian velocity bound)"


def _zu(j1, j3, j4, j5, j6, velocity, limits=_STD, rpy5=(H, 0.0, 0.0), axis5=_Z,
        rpy6=(-H, 0.0, 0.0), axis6=_Z) -> tuple[Row, ...]:
    """The rows of a Zu-structure file: J1 (xyz), J2 at J1 turned by rpy (H, 0, 0), J3, J4
    (xyz, no rotation), J5 and J6 (xyz with their rpy and axes, by default JAKA's usual ones)."""
    origins = ((j1, _R0, _Z), ((0.0, 0.0, 0.0), (H, 0.0, 0.0), _Z), (j3, _R0, _Z),
               (j4, _R0, _Z), (j5, rpy5, axis5), (j6, rpy6, axis6))
    return tuple(Row(tuple(map(float, xyz)), tuple(map(float, rpy)), tuple(map(float, axis)),
                     lo, hi, v)
                 for (xyz, rpy, axis), (lo, hi), v in zip(origins, limits, velocity))


def _rows(*rows) -> tuple[Row, ...]:
    return tuple(Row(tuple(map(float, xyz)), tuple(map(float, rpy)), tuple(map(float, ax)),
                     lo, hi, v) for xyz, rpy, ax, lo, hi, v in rows)


_V314 = (3.14,) * 6
_V209_314 = (2.09, 2.09, 2.09, 3.14, 3.14, 3.14)
_V18 = (2.09, 2.09, 3.14, 3.14, 3.14, 3.14)
_V20 = (2.09, 2.09, 2.09, 3.84, 3.84, 3.84)

# zu20's chain, also used for the a20 (DEVIATIONS).
_ZU20_ROWS = _zu((0.0044104, -0.00027834, 0.1965), (0.897, 0, 0), (0.7445, 0, -0.18835),
                 (0, -0.1385, 0), (-0.00025841, 0.1205, 0.00025841), _V20)

ARMS: dict[str, Arm] = {a.name: a for a in (
    Arm("zu3", "JAKA Zu 3", (-0.002, 0.0, -0.00001),
        _zu((0, 0, 0.15055), (0.248, 0, 0), (0.228, 1.1925e-05, -0.115), (0, -0.1175, 0),
            (0, 0.1065, 0), (3.14, 3.14, 3.14, 3.84, 3.84, 3.84)),
        3, 1500, _LIBJAKA, "zu", _POSE_1, 12.0, "commonly published weight (unverified)"),
    Arm("zu5", "JAKA Zu 5", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.12015), (0.43, 0, 0), (0.3685, -1.185e-05, -0.114), (0, -0.1135, 0),
            (0, 0.107, 0), _V314),
        5, 3000, _LIBJAKA, "zu", _POSE_1, 23.0,
        "JAKA's specification as quoted by a third-party MuJoCo model of the Zu 5"),
    Arm("zu7", "JAKA Zu 7", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.12015), (0.36, 0, 0), (0.30353, 0, -0.11501), (0, -0.1135, 0),
            (0, 0.107, 0), _V314),
        7, 2500, _LIBJAKA, "zu", _POSE_1, 22.0, "commonly published weight (unverified)"),
    Arm("zu12", "JAKA Zu 12", (0.0, 0.0, 0.04),
        _zu((0, 0, 0.10265), (0.595, 0, 0), (0.5715, 0, -0.1315), (0, -0.115, 0),
            (0, 0.1035, 0), _V209_314),
        12, 3000, _LIBJAKA, "zu", _POSE_1, 41.0, "commonly published weight (unverified)"),
    Arm("zu18", "JAKA Zu 18", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.14265), (0.51, 0, 0), (0.4, 0, -0.154), (0, -0.115, 0),
            (0, 0.1035, 0), _V18),
        18, 3500, _LIBJAKA, "zu", _POSE_1, 35.0, "commonly published weight (unverified)"),
    Arm("zu20", "JAKA Zu 20", (0.005, 0.0, 0.0), _ZU20_ROWS,
        20, 5000, _LIBJAKA, "zu", _POSE_1),
    Arm("zu30", "JAKA Zu 30", (0.005, 0.0, 0.0),
        _zu((0.0044104, -0.00027834, 0.1965), (0.6625, 0, 0), (0.549, 0, -0.18835),
            (0, -0.1385, 0), (0.00039033, 0.1205, 0), _V20),
        30, 4200, _LIBJAKA, "zu", _POSE_1),
    Arm("c5", "JAKA C5", (0.0, 0.0, 0.0),
        _zu((0, -0.00022535, 0.12015), (0.43, 0, 0), (0.3685, -1.185e-05, -0.114),
            (0, -0.1135, 0), (0, 0.107, 0), _V314),
        5, 3000, "as the Zu 5 (same chain; libjaka has no C models)", "zu", _POSE_1),
    Arm("c7", "JAKA C7", (0.0, 0.0, 0.0),
        _zu((0, -0.00022535, 0.12015), (0.36, 0, 0), (0.3035, 0, -0.11501), (0, -0.1135, 0),
            (0, 0.107, 0), _V314),
        7, 2500, "as the Zu 7 (same chain; libjaka has no C models)", "zu", _POSE_1),
    Arm("c12", "JAKA C12", (0.0, 0.0, 0.0),      # JAKA: 0 0 0.04 (DEVIATIONS)
        _zu((0, -0.0002479, 0.14265), (0.595, 0, 0), (0.5715, 0, -0.1315), (0, -0.115, 0),
            (-0.00025841, 0.1035, -0.00025841),
            (2.09, 2.09, 2.09, 2.62, 2.62, 2.62), rpy5=(H, 0.0, -PI), axis5=(0.0, 0.0, -1.0),
            rpy6=(H, 0.0, PI)),
        12, 3000, "as the Zu 12 (same chain; libjaka has no C models)", "zu", _POSE_1),
    Arm("pro5", "JAKA Pro 5", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.12015), (0.43, 0, 0), (0.3685, -1.185e-05, -0.114), (0, -0.1135, 0),
            (0, 0.107, 0), _V314),
        5, 3000, _LIBJAKA, "zu", _POSE_1),
    Arm("pro7", "JAKA Pro 7", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.12015), (0.36, 0, 0), (0.3035, 0, -0.11502), (0, -0.1135, 0),
            (0, 0.107, 0), _V314),
        7, 2500, _LIBJAKA, "zu", _POSE_1),
    Arm("pro12", "JAKA Pro 12", (0.0, 0.0, 0.0),    # JAKA: 0 0 0.04 (DEVIATIONS)
        _zu((0, -0.00018758, 0.14265), (0.595, 0, 0), (0.5715, 0, -0.1315), (0, -0.115, 0),
            (0.00025836, 0.1035, 0.00025795), _V209_314),
        12, 3000, _LIBJAKA, "zu", _POSE_1),
    Arm("pro16", "JAKA Pro 16", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.1965), (0.819, 0, 0), (0.687, 0, -0.15801), (0, -0.14415, 0),
            (0, 0.12665, 0), _V209_314),
        16, 3500, _LIBJAKA, "zu", _POSE_1),
    Arm("pro18", "JAKA Pro 18", (0.0, 0.0, 0.0),
        _zu((0, 0, 0.14265), (0.51, 0, 0), (0.4, 0, -0.154), (0, -0.115, 0),
            (0.00025836, 0.1035, 0.00025795), _V18),
        18, 3500, _LIBJAKA, "zu", _POSE_1),
    Arm("s5", "JAKA S5", (0.0, 0.0, 0.0),
        _zu((0, -0.00022535, 0.12015), (0.43, 0, 0), (0.3685, 0, -0.114), (0, -0.1135, 0),
            (0.00026137, 0.1175, 0.00025782), _V314),
        5, 3000, _LIBJAKA, "zu", _POSE_1),
    # The S7 file orients its link frames differently (same axes, signs and lengths as the
    # Zu 7 but d6) and turns the flange frame 180° about its z axis.
    Arm("s7", "JAKA S7", (0.0, 0.0002282, 0.0),
        _rows(((0, -0.00022535, 0.12015), _R0, _Z, -6.28, 6.28, 3.14),
              ((0, 0, 0), (H, H, 0), _Z, -1.48, 4.62, 3.14),
              ((0, 0.36, 0), _R0, _Z, -3.05, 3.05, 3.14),
              ((0, 0.3035, -0.11501), (0, 0, -H), _Z, -1.48, 4.62, 3.14),
              ((0, 0.1135, 0), (-H, 0, 0), _Z, -6.28, 6.28, 3.14),
              ((0, -0.1175, 0), (H, 0, 0), _Z, -6.28, 6.28, 3.14)),
        7, 2500, _LIBJAKA, "zu", _POSE_1),
    Arm("s12", "JAKA S12", (0.0, 0.0, 0.0),
        _zu((0, -0.00018758, 0.14265), (0.595, 0, 0), (0.5715, 0, -0.1315), (0, -0.115, 0),
            (0.00025822, 0.112, 0.00025865), _V209_314),
        12, 3000, _LIBJAKA, "zu", _POSE_1),
    Arm("a5", "JAKA A5", (0.0, 0.0, 0.0),
        _zu((0, -0.00022535, 0.12015), (0.43, 0, 0), (0.3685, 0, -0.115), (0, -0.1135, 0),
            (0, 0.107, 0), (3.665,) * 6,
            limits=((-6.28, 6.28), (-1.48, 4.628), (-3.05, 3.05), (-1.48, 4.62),
                    (-6.28, 6.28), (-6.28, 6.28)),
            rpy5=(H, -0.00010901, 0.0), rpy6=(-H, 0.0, -0.00010901),
            axis6=(-0.00010901, 0.0, 1.0)),
        5, 3500, _LIBJAKA, "zu", _POSE_1),
    # Forearm roll: J4 along the forearm (docs/models.md, "Three kinematic structures").
    Arm("a12", "JAKA A12", (0.0, 0.0, 0.0),
        _rows(((9.3823e-05, 0, 0.14265), _R0, _Z, -6.28, 6.28, 2.62),
              ((0, 0, 0), (H, 0, 0), _Z, -6.28, 6.28, 2.62),
              ((0.77, 0, 0.0375), (0, 0, H), _Z, -6.28, 6.28, 3.67),
              ((0, -0.5515, 0), (-H, 0, -PI), _Z, -6.28, 6.28, 3.67),
              ((0, -0.115, 0), (-H, -H, PI), _Z, -6.28, 6.28, 3.67),
              ((0, -0.1035, 0), (H, 0, 0), _Z, -6.28, 6.28, 3.67)),
        12, 4000, _LIBJAKA, "forearm_roll", (0.0, 90.0, -90.0, 0.0, 0.0, 0.0)),
    # The A20 file is broken (DEVIATIONS): the Zu 20 chain until an A20 confirms it.
    Arm("a20", "JAKA A20", (0.005, 0.0, 0.0), _ZU20_ROWS,
        20, 5000, _LIBJAKA, "zu", _POSE_1),
    # Spherical wrist; JAKA's extra identity frame dummy_tcp is the driver's flange.
    Arm("minicobo", "JAKA MiniCobo", (0.0, 0.0, 0.0),
        _rows(((0, 0, 0.187), _R0, _Z, -6.28, 6.28, 1.57),
              ((0, -0.006, 0), (H, -H, 0), _Z, -2.09, 2.09, 1.57),
              ((0.21, 0, 0), (0, 0, -H), _Z, -2.27, 2.27, 1.57),
              ((0, 0.2105, 0), (-H, 0, 0), _Z, -6.28, 6.28, 1.57),
              ((0, 0, 0), (H, 0, 0), _Z, -2.09, 2.09, 1.57),
              ((0, 0.1593, 0), (-H, 0, 0), _Z, -6.28, 6.28, 1.57)),
        1, 1000, _LIBJAKA, "spherical_wrist", (0.0, 0.0, 90.0, 0.0, 90.0, 0.0)),
)}

MODEL_NAMES = tuple(ARMS)

# Where this project does not take JAKA's file as written, and why (docs/models.md repeats it).
DEVIATIONS = {
    "c12": "JAKA's file lifts the base link 40 mm above its `world` (J2 axis 182.65 mm up, the "
           "base mesh at 40…80 mm); relative to the mounting face the arm is the Zu 12's "
           "(142.65 mm), so the driver's base_link is JAKA's base link, not its `world`",
    "pro12": "as the C12: the 40 mm `world` → base offset is dropped",
    "a20": "JAKA's file is broken (J1 axis reversed, J2–J6 axes tilted up to 3.8°, flange up "
           "to 117 mm off the Zu 20); the Zu 20 chain, which libjaka also gives the A20, is used "
           "until an A20 confirms it",
    "zu12": "JAKA declares the joints `continuous` although it writes limits; here they are "
            "`revolute` so the limits hold",
    "s5": "JAKA's ROS 1 file differs (no J1 offset, base 0.1 mm up); the newer ROS 2 file is used",
    "s12": "JAKA's ROS 1 file offsets the base to cancel the J1/J6 offsets; the newer ROS 2 file "
           "is used",
    "zu30": "JAKA's ROS 1 file has no 5 mm `world` → base offset; the newer ROS 2 file is used",
    "minicobo": "JAKA's identity frame dummy_tcp after Link_6 is the driver's flange",
    "a12 home": "JAKA's pose_1 for the A12 (the Zu's, copied into its SRDF) puts J6 in line "
                "with J4, a singular pose no Cartesian move can start from; the twin starts "
                "at (0, 90°, -90°, 0, 0, 0) instead: the same arm, tool pointing down",
}
