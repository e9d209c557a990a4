"""Pictures of the twin: the visual shapes of a model at given joint angles, rendered offscreen
to an RGB array or a PNG file.

No display is needed: the GL context is EGL (Mesa's llvmpipe renders on the CPU when there is
no GPU). It is created here rather than through ``mujoco.Renderer`` and ``MUJOCO_GL``, because
MuJoCo picks its default context once, when ``mujoco`` is first imported — in the node that
happens long before anybody asks for a picture.

The camera is fixed per model (it frames the arm's reach, not the current pose), so two
pictures of the same model can be compared pixel by pixel. Units: joint angles rad, camera
distance m, angles deg, image size px.
"""
from __future__ import annotations

import os
import struct
import sys
import threading
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence

import mujoco
import numpy as np

from ..common.models import RobotModel
from .twin_model import build_twin_model

GRID_STEP = 0.1            # m between floor grid lines: a scale bar in every picture
GRID_RGBA = (0.45, 0.45, 0.48, 1.0)
VISUAL_GROUP = 1            # MuJoCo's URDF import puts <visual> shapes in geom group 1
BACKGROUND = (236, 240, 245)    # RGB behind the floor's horizon: a light sky, like the docs


@dataclass(frozen=True)
class View:
    """A free camera: looks at ``(ahead, 0, height)`` × reach (base frame) from ``distance`` ×
    reach away; ``azimuth`` deg from +x towards +y, ``elevation`` deg (negative = from above).
    Relative to the reach so every model fills the picture alike."""

    azimuth: float = 140.0
    elevation: float = -18.0
    distance: float = 1.8
    ahead: float = 0.25
    height: float = 0.4


def gl_context(width: int, height: int):
    """An EGL context: headless, and on a machine without a GPU Mesa's llvmpipe renders on the
    CPU. (MuJoCo's OSMesa and GLFW contexts were not used: Debian's OSMesa is not installed by
    default and GLFW needs an X display.)"""
    from mujoco.egl import GLContext   # sets PYOPENGL_PLATFORM=egl unless it is set otherwise
    return GLContext(width, height)


class TwinCamera:
    """Renders one model (with the workcell ``scene``, if any) at ``width`` × ``height`` px.

    Owns its own ``MjModel`` (visual shapes kept) and ``MjData``: the live twin's are never
    touched, only its joint angles are copied in. Thread-safe: the GL context is made current
    for each picture and released afterwards, under a lock, so any thread may call
    :meth:`render` (rospy serves every service call in a thread of its own).
    """

    def __init__(self, model: RobotModel, scene: Optional[str] = None, *, width: int = 800,
                 height: int = 600, view: View = View()):
        if not (16 <= width <= 4096 and 16 <= height <= 4096):
            raise ValueError(f"image size {width}x{height} px is outside 16–4096 px")
        self.model = model
        self.width, self.height = width, height
        m = build_twin_model(model, scene, visual=True)
        m.vis.global_.offwidth = max(width, m.vis.global_.offwidth)
        m.vis.global_.offheight = max(height, m.vis.global_.offheight)
        # The model has no lights of its own: a stronger ambient share of the camera's
        # headlight keeps the floor from going dark at grazing angles.
        m.vis.headlight.ambient[:] = 0.45
        m.vis.headlight.diffuse[:] = 0.55
        self._m = m
        self._d = mujoco.MjData(m)
        self._lock = threading.Lock()
        self._camera, reach = self._frame(view)
        self._grid = _grid_lines(1.5 * reach)
        self._option = mujoco.MjvOption()
        # Collision shapes (group 0) are not what the arm looks like; the floor and scene
        # obstacles are group 0 too, so they are added back as static geoms (see below).
        self._option.geomgroup[:] = 0
        self._option.geomgroup[VISUAL_GROUP] = 1
        self._perturb = mujoco.MjvPerturb()      # nobody drags the arm in a picture
        self._world_option = mujoco.MjvOption()
        self._world_option.geomgroup[:] = 0
        self._world_option.geomgroup[0] = 1
        self._scene = mujoco.MjvScene(m, maxgeom=1000)
        self._gl = gl_context(width, height)
        with self._gl.as_current():
            self._context = mujoco.MjrContext(m, mujoco.mjtFontScale.mjFONTSCALE_100)
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
        self._viewport = mujoco.MjrRect(0, 0, width, height)

    def _frame(self, view: View) -> tuple[mujoco.MjvCamera, float]:
        """The camera for this model, and the model's reach (m): the farthest body from the
        base with every joint at 0 (the JAKA arms are stretched out there)."""
        d = mujoco.MjData(self._m)
        mujoco.mj_kinematics(self._m, d)
        reach = float(np.max(np.linalg.norm(d.xpos, axis=1)))
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = (view.ahead * reach, 0.0, view.height * reach)
        cam.distance = view.distance * reach
        cam.azimuth, cam.elevation = view.azimuth, view.elevation
        return cam, reach

    def render(self, joints: Sequence[float]) -> np.ndarray:
        """An RGB picture, ``uint8`` array of shape (height, width, 3), of the arm at
        ``joints`` (6 values, rad)."""
        q = np.asarray(joints, float)
        if q.shape != (6,) or not np.all(np.isfinite(q)):
            raise ValueError(f"joints must be 6 finite angles in rad, got {list(np.ravel(q))}")
        rgb = np.empty((self.height, self.width, 3), np.uint8)
        depth = np.empty((self.height, self.width), np.float32)
        with self._lock:
            if self._gl is None:
                raise RuntimeError("this TwinCamera is closed")
            self._d.qpos[:6] = q
            mujoco.mj_kinematics(self._m, self._d)
            mujoco.mjv_updateScene(self._m, self._d, self._option, self._perturb, self._camera,
                                   int(mujoco.mjtCatBit.mjCAT_ALL), self._scene)
            self._show_world_geoms()
            self._draw_grid()
            with self._gl.as_current():
                mujoco.mjr_render(self._viewport, self._scene, self._context)
                mujoco.mjr_readPixels(rgb, depth, self._viewport, self._context)
        # Nothing was drawn where the depth buffer kept its clear value (far plane): the
        # clear colour is black, a light sky reads better in docs.
        rgb[depth >= 1.0] = BACKGROUND
        return np.flipud(rgb)          # OpenGL's rows run bottom-up

    def _show_world_geoms(self) -> None:
        """Add the floor and workcell (world body, group 0) that the group filter left out;
        static geoms only, so the moving links' collision shapes stay hidden."""
        mujoco.mjv_addGeoms(self._m, self._d, self._world_option, self._perturb,
                            int(mujoco.mjtCatBit.mjCAT_STATIC), self._scene)

    def _draw_grid(self) -> None:
        scn = self._scene
        for a, b in self._grid:
            if scn.ngeom >= scn.maxgeom:
                return
            geom = scn.geoms[scn.ngeom]
            mujoco.mjv_initGeom(geom, mujoco.mjtGeom.mjGEOM_LINE, np.zeros(3), np.zeros(3),
                                np.eye(3).ravel(), np.array(GRID_RGBA, np.float32))
            mujoco.mjv_connector(geom, mujoco.mjtGeom.mjGEOM_LINE, 1.5, a, b)
            scn.ngeom += 1

    def save(self, joints: Sequence[float], path: str | os.PathLike) -> Path:
        """Render ``joints`` (rad) and write the picture to ``path`` as PNG; returns the path."""
        return write_png(path, self.render(joints))

    def close(self) -> None:
        with self._lock:
            if self._gl is not None:
                with self._gl.as_current():
                    self._context.free()
                self._gl.free()
                self._gl = None

    def __enter__(self) -> "TwinCamera":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _grid_lines(half_width: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """End points (m) of a floor grid, ``GRID_STEP`` apart, covering ±``half_width``; lifted
    1 mm so the floor does not hide it."""
    n = int(np.ceil(half_width / GRID_STEP))
    edge = n * GRID_STEP
    lines = []
    for i in range(-n, n + 1):
        c = i * GRID_STEP
        lines.append((np.array([c, -edge, 1e-3]), np.array([c, edge, 1e-3])))
        lines.append((np.array([-edge, c, 1e-3]), np.array([edge, c, 1e-3])))
    return lines


def write_png(path: str | os.PathLike, rgb: np.ndarray) -> Path:
    """Write an RGB ``uint8`` array (height, width, 3) as an 8-bit PNG, stdlib only."""
    rgb = np.ascontiguousarray(rgb, dtype=np.uint8)
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(f"expected an RGB array (h, w, 3), got shape {rgb.shape}")
    h, w, _ = rgb.shape
    # Each scanline starts with its filter type; 0 (none) keeps the encoder trivial and zlib
    # still shrinks the flat floor and sky well.
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rgb.reshape(h, w * 3)], axis=1)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n"
           + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw.tobytes(), 6))
           + chunk(b"IEND", b""))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(png)
    tmp.replace(path)      # a reader never sees half a file
    return path


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``rosrun jaka_driver snapshot --model zu5 --joints 0 1.57 -1.57 1.57 1.57 0 -o arm.png``"""
    import argparse

    from ..common.models import MODEL_NAMES, load_model

    parser = argparse.ArgumentParser(
        prog="snapshot", description="Render the MuJoCo twin of a JAKA arm at given joint "
        "angles to a PNG, offscreen (no display needed).")
    parser.add_argument("--model", default="zu5", help=f"one of {', '.join(MODEL_NAMES)}")
    parser.add_argument("--joints", nargs=6, type=float, metavar="RAD",
                        help="joint_1 … joint_6 in rad (default: the model's home pose, "
                             "where the twin starts)")
    parser.add_argument("-o", "--output", help="PNG file to write (default: <model>.png)")
    parser.add_argument("--scene", help="workcell obstacles, MJCF or YAML (as ~scene)")
    parser.add_argument("--width", type=int, default=800, help="px (default 800)")
    parser.add_argument("--height", type=int, default=600, help="px (default 600)")
    parser.add_argument("--azimuth", type=float, default=View.azimuth, help="deg")
    parser.add_argument("--elevation", type=float, default=View.elevation, help="deg")
    args = parser.parse_args(argv)
    name = args.model.lower()
    if name not in MODEL_NAMES:
        parser.error(f"unknown model {args.model!r}; expected one of {', '.join(MODEL_NAMES)}")
    output = args.output or f"{name}.png"
    view = View(azimuth=args.azimuth, elevation=args.elevation)
    try:
        model = load_model(name)
        joints = model.home.tolist() if args.joints is None else args.joints
        with TwinCamera(model, args.scene, width=args.width, height=args.height,
                        view=view) as camera:
            path = camera.save(joints, output)
    except (ValueError, RuntimeError, ImportError, OSError) as exc:
        print(f"snapshot: {exc}", file=sys.stderr)
        return 1
    print(f"wrote {path} ({args.width}x{args.height} px, {name} at "
          f"[{', '.join(f'{q:g}' for q in joints)}] rad)")
    return 0
