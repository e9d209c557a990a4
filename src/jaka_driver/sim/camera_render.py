"""Colour and depth pictures of the twin's configured cameras, rendered offscreen (EGL; Mesa's
llvmpipe on the CPU where there is no GPU), one frame at a time from a copy of the twin's
joint positions (``qpos``: the arm, and whatever else of the scene moves).

Owns its own visual model (the physics twin's model with its ``<visual>`` shapes and a MuJoCo
camera per :class:`~jaka_driver.common.camera_spec.CameraSpec`) and ``MjData``: the live twin's
are never touched. MuJoCo cameras look along their -z with y up; the optical frame looks along
z with y down: a half turn about x apart. Multisampling is off (a depth pixel on an edge would
otherwise blend the near and the far surface into a point of neither) and round shapes are
cut into :data:`SLICES` around and :data:`STACKS` along, so depth and CameraInfo agree to well
under a millimetre (jaka_driver.common.pinhole says how the projection is stated).

Not thread-safe: one thread renders (the GL context is current in it). Units: m, rad, px.
"""
from __future__ import annotations

from typing import Optional, Sequence

import mujoco
import numpy as np

from ..common.camera_spec import CameraSpec
from ..common.models import RobotModel
from ..common.sensor_spec import ForceSensorSpec
from .collisions import ARM_BODIES
from .ft_sensor import TOOL_BODY
from .snapshot import VISUAL_GROUP, gl_context
from .twin_model import build_twin_model

HIDDEN_GROUP = 3            # the arm's collision capsules are moved here: not what it looks like
# Round shapes' facets. Slices (around) make the outline: 64 keep a ball's edge round. Stacks
# (along) cost as much again for little: llvmpipe spends its time on triangles, not pixels.
# Measured on the 40 mm ball of test/data/camera_cell.yaml 1 m away, and 640 × 480 colour +
# depth p50 on the 2-core machine (one process, side by side): 64 stacks 0.06 mm off the
# ball's surface at most, 7.4–8.2 ms; 32: 0.09 mm, 5.6 ms; 16: 0.24 mm, 3.7–4.2 ms; 8: 0.81 mm.
SLICES = 64                 # MuJoCo's default: 28
STACKS = 16                 # MuJoCo's default


class CameraRenderer:
    """Renders ``cameras`` of ``model`` in ``scene`` (``force_sensor`` and ``gripper`` as the
    twin has them, so the joint positions line up). Make it, render with it and close it in one thread."""

    def __init__(self, model: RobotModel, cameras: Sequence[CameraSpec],
                 scene: Optional[str] = None, force_sensor: Optional[ForceSensorSpec] = None,
                 gripper: str = "none"):
        self._specs = {c.name: c for c in cameras}
        m = build_twin_model(model, scene, visual=True, force_sensor=force_sensor,
                             gripper=gripper, cameras=cameras)
        m.vis.global_.offwidth = max([c.width for c in cameras] + [m.vis.global_.offwidth])
        m.vis.global_.offheight = max([c.height for c in cameras] + [m.vis.global_.offheight])
        m.vis.quality.offsamples = 0
        m.vis.quality.numslices, m.vis.quality.numstacks = SLICES, STACKS
        m.vis.headlight.ambient[:] = 0.45
        m.vis.headlight.diffuse[:] = 0.55
        arm = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b)
               for b in ARM_BODIES + [TOOL_BODY]}
        for g in range(m.ngeom):
            if m.geom_bodyid[g] in arm and m.geom_group[g] != VISUAL_GROUP:
                m.geom_group[g] = HIDDEN_GROUP
        self._m = m
        self._d = mujoco.MjData(m)
        self._option = mujoco.MjvOption()
        self._option.geomgroup[:] = 0
        self._option.geomgroup[0] = self._option.geomgroup[VISUAL_GROUP] = 1
        self._perturb = mujoco.MjvPerturb()
        self._scene = mujoco.MjvScene(m, maxgeom=2000)
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self._ids = {name: mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_CAMERA, name)
                     for name in self._specs}
        self._gl = gl_context(m.vis.global_.offwidth, m.vis.global_.offheight)
        self._gl.make_current()
        self._context = mujoco.MjrContext(m, mujoco.mjtFontScale.mjFONTSCALE_100)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
        # Depth read as MuJoCo's renderer reads it: 1 at the near plane, 0 at the far one
        # (it draws with reversed z), then undone below.
        self._context.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        extent = m.stat.extent
        near = np.float32(m.vis.map.znear * extent)
        far = np.float32(m.vis.map.zfar * extent)
        # OpenGL's perspective matrix terms in float32, as glFrustum makes them, turned for
        # reversed z (mujoco.Renderer does the same)
        c = -(far + near) / (far - near)
        d = -(np.float32(2) * far * near) / (far - near)
        self._c, self._d_coef = float(np.float32(-0.5) * c - np.float32(0.5)), \
            float(np.float32(-0.5) * d)

    def render(self, name: str, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rgb (h, w, 3) uint8, depth (h, w) float32 m, NaN where nothing is seen) of camera
        ``name`` with the twin's joints at ``qpos`` (its whole ``qpos``, or the arm's 6)."""
        spec = self._specs[name]
        m, d = self._m, self._d
        n = min(len(qpos), m.nq)
        d.qpos[:n] = qpos[:n]
        mujoco.mj_kinematics(m, d)
        mujoco.mj_camlight(m, d)
        self._camera.fixedcamid = self._ids[name]
        mujoco.mjv_updateScene(m, d, self._option, self._perturb, self._camera,
                               int(mujoco.mjtCatBit.mjCAT_ALL), self._scene)
        rect = mujoco.MjrRect(0, 0, spec.width, spec.height)
        rgb = np.empty((spec.height, spec.width, 3), np.uint8)
        raw = np.empty((spec.height, spec.width), np.float32)
        self._gl.make_current()
        mujoco.mjr_render(rect, self._scene, self._context)
        mujoco.mjr_readPixels(rgb, raw, rect, self._context)
        with np.errstate(divide="ignore"):
            depth = (self._d_coef / (raw.astype(np.float64) + self._c)).astype(np.float32)
        depth[raw <= 0.0] = np.nan          # the far plane's clear value: nothing there
        return np.ascontiguousarray(np.flipud(rgb)), np.ascontiguousarray(np.flipud(depth))

    def close(self) -> None:
        if self._gl is not None:
            self._gl.make_current()
            self._context.free()
            self._gl.free()
            self._gl = None
