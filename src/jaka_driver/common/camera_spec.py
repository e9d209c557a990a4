"""A camera of the twin as its configuration describes it: the scene file's ``cameras:`` list
and the node's ``~wrist_camera`` (docs/twin.md, "Cameras"), checked once here so a bad entry
is refused at start with the field, the value and the limit.

A camera is fixed in the cell (``mount: world``, its pose from ``base_link``) or on the flange
(``mount: flange``, its pose from ``flange``). The pose given is that of ``<name>_link`` in
ROS's body convention (REP 103: x forward = the viewing direction, y left, z up), as camera
drivers' URDFs have it; ``<name>_optical_frame`` sits at the same origin in the optical
convention (z forward, x right, y down): :data:`LINK_TO_OPTICAL`. ``euler`` is read as the
scene file's obstacles are: rotations about x, then the new y, then the new z (MuJoCo's
``xyz``), ``R = Rx(a) · Ry(b) · Rz(c)``.

Units: m, rad (``euler``), degrees (``fovy``, the vertical field of view, as MuJoCo's cameras
have it), px (``width``, ``height``, ``fx``), Hz (``rate``).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Iterable, Mapping, Optional

import numpy as np

MOUNTS = {"world": "base_link", "flange": "flange"}     # mount → the TF parent of its link
SIZE_PX = (16, 4096)          # px, width and height (MuJoCo's offscreen buffer)
RATE_HZ = (0.1, 60.0)         # Hz
FOVY_DEG = (1.0, 170.0)       # deg
REACH_M = 10.0                # m, the farthest a camera may sit from its parent frame
NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")     # a ROS name part: topics and frames use it
FIELDS = ("name", "width", "height", "fovy", "fx", "rate", "mount", "pos", "euler",
          "point_cloud")

#: ``<name>_link`` (x forward, y left, z up) → ``<name>_optical_frame`` (z forward, x right,
#: y down): the optical frame's axes in the link's frame, as columns
LINK_TO_OPTICAL = np.array([[0.0, 0.0, 1.0, 0.0],
                            [-1.0, 0.0, 0.0, 0.0],
                            [0.0, -1.0, 0.0, 0.0],
                            [0.0, 0.0, 0.0, 1.0]])
LINK_TO_OPTICAL.setflags(write=False)


@dataclass(frozen=True, eq=False)
class CameraSpec:
    """One checked camera (see the module). ``fovy`` deg whatever the file said (``fx`` is
    turned into it); ``pos`` m and ``euler`` rad of ``<name>_link`` in :attr:`parent_frame`."""

    name: str
    width: int
    height: int
    fovy: float
    rate: float
    mount: str
    pos: tuple
    euler: tuple
    point_cloud: bool = False

    @property
    def parent_frame(self) -> str:
        return MOUNTS[self.mount]

    @property
    def link_frame(self) -> str:
        return f"{self.name}_link"

    @property
    def optical_frame(self) -> str:
        return f"{self.name}_optical_frame"

    def link_pose(self) -> np.ndarray:
        """4×4 (m): ``<name>_link`` in :attr:`parent_frame`."""
        T = np.eye(4)
        T[:3, :3] = euler_xyz(self.euler)
        T[:3, 3] = self.pos
        return T

    def optical_pose(self) -> np.ndarray:
        """4×4 (m): ``<name>_optical_frame`` in :attr:`parent_frame`."""
        return self.link_pose() @ LINK_TO_OPTICAL


def euler_xyz(euler) -> np.ndarray:
    """``R = Rx(a) · Ry(b) · Rz(c)`` (rad): the scene file's reading of ``euler``."""
    a, b, c = (float(v) for v in euler)
    ca, sa, cb, sb, cc, sc = math.cos(a), math.sin(a), math.cos(b), math.sin(b), \
        math.cos(c), math.sin(c)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return rx @ ry @ rz


#: ``~wrist_camera``'s camera: on the flange's side, 70 mm off its axis, looking along the
#: flange's z (out of the flange, where the tool points); a RealSense-like 60° × 78° view
WRIST_CAMERA = {"name": "wrist_camera", "mount": "flange", "width": 640, "height": 480,
                "fovy": 60.0, "rate": 10.0, "pos": [0.0, -0.07, 0.02],
                "euler": [0.0, -math.pi / 2, 0.0]}


def _number(where: str, field: str, value, low: float, high: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: {field} is {value!r}, expected a number in "
                         f"{low:g}–{high:g}") from None
    if not (low <= v <= high):
        raise ValueError(f"{where}: {field} is {value!r}, outside {low:g}–{high:g}")
    return v


def _whole(where: str, field: str, value, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value):
        raise ValueError(f"{where}: {field} is {value!r}, expected a whole number of px in "
                         f"{low}–{high}")
    if not low <= int(value) <= high:
        raise ValueError(f"{where}: {field} is {value!r} px, outside {low}–{high} px")
    return int(value)


def _triple(where: str, field: str, value, limit: float) -> tuple:
    try:
        v = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        v = ()
    if len(v) != 3 or not all(math.isfinite(x) and abs(x) <= limit for x in v):
        raise ValueError(f"{where}: {field} is {value!r}, expected 3 numbers within "
                         f"±{limit:g}")
    return v


def camera_from(entry: Mapping, where: str) -> CameraSpec:
    """One camera from its configuration entry (a mapping with :data:`FIELDS`); ValueError
    naming ``where``, the field, the value and the limit if anything is wrong."""
    if not isinstance(entry, Mapping):
        raise ValueError(f"{where}: expected a mapping of {', '.join(FIELDS)}, got {entry!r}")
    unknown = sorted(set(entry) - set(FIELDS))
    if unknown:
        raise ValueError(f"{where}: unknown field {unknown[0]!r}; a camera has "
                         f"{', '.join(FIELDS)}")
    name = entry.get("name")
    if not isinstance(name, str) or not NAME.match(name):
        raise ValueError(f"{where}: name is {name!r}, expected letters, digits and _ "
                         "starting with a letter (it names topics and frames)")
    where = f"{where} ({name})"
    mount = entry.get("mount", "world")
    if mount not in MOUNTS:
        raise ValueError(f"{where}: mount is {mount!r}, expected one of {', '.join(MOUNTS)}")
    width = _whole(where, "width", entry.get("width", 640), *SIZE_PX)
    height = _whole(where, "height", entry.get("height", 480), *SIZE_PX)
    if "fx" in entry and "fovy" in entry:
        raise ValueError(f"{where}: give fovy or fx, not both (square pixels: fy = fx)")
    if "fx" in entry:
        # square pixels, principal point at the centre: fy = fx = (h/2) / tan(fovy/2)
        low, high = (height / 2 / math.tan(math.radians(f) / 2) for f in FOVY_DEG[::-1])
        fx = _number(where, "fx", entry["fx"], low, high)
        fovy = math.degrees(2 * math.atan(height / 2 / fx))
    else:
        fovy = _number(where, "fovy", entry.get("fovy", 60.0), *FOVY_DEG)
    rate = _number(where, "rate", entry.get("rate", 10.0), *RATE_HZ)
    pos = _triple(where, "pos", entry.get("pos", (0.0, 0.0, 0.0)), REACH_M)
    euler = _triple(where, "euler", entry.get("euler", (0.0, 0.0, 0.0)), 4 * math.pi)
    cloud = entry.get("point_cloud", False)
    if not isinstance(cloud, bool):
        raise ValueError(f"{where}: point_cloud is {cloud!r}, expected true or false")
    return CameraSpec(name, width, height, fovy, rate, mount, pos, euler, cloud)


def cameras_from(entries: Optional[Iterable], wrist_camera: bool = False,
                 where: str = "cameras") -> tuple[CameraSpec, ...]:
    """Every camera: the entries of a scene file's ``cameras:`` list, and
    :data:`WRIST_CAMERA` when ``wrist_camera`` (unless an entry already has its name).
    Names must differ: they name topics and frames."""
    if entries is None:
        entries = []
    if isinstance(entries, (str, bytes, Mapping)) or not isinstance(entries, Iterable):
        raise ValueError(f"{where}: expected a list of cameras, got {entries!r}")
    specs = [camera_from(e, f"{where}[{i}]") for i, e in enumerate(entries)]
    names = [s.name for s in specs]
    if wrist_camera and WRIST_CAMERA["name"] not in names:
        specs.append(camera_from(WRIST_CAMERA, "~wrist_camera"))
        names.append(WRIST_CAMERA["name"])
    for name in names:
        if names.count(name) > 1:
            raise ValueError(f"{where}: two cameras are named {name!r}; names must differ")
    return tuple(specs)


def cameras_of_scene(scene: Optional[str], wrist_camera: bool = False) -> tuple[CameraSpec, ...]:
    """The cameras of a YAML scene file's ``cameras:`` list (an MJCF scene has none) and the
    wrist camera when asked for; ValueError as :func:`camera_from`."""
    entries = None
    if scene and str(scene).lower().endswith((".yaml", ".yml")):
        import yaml
        with open(scene) as f:
            data = yaml.safe_load(f) or {}
        entries = data.get("cameras") if isinstance(data, Mapping) else None
        return cameras_from(entries, wrist_camera, where=f"{scene}: cameras")
    return cameras_from(entries, wrist_camera)
