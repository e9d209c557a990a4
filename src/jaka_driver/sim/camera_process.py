"""The cameras' renderer in a process of its own (:class:`RenderProcess`), so that a frame's
rendering never competes with the arm for the node's interpreter or its scheduling.

Why a process and not a thread: measured on a 2-core machine in side-by-side windows
(bench/cameras.py), rendering 640 × 480 colour + depth at 10 Hz in a thread of the node, at
nice +10, stretched the state topics' inter-arrival p99 from 8.2 to 9.9–11.3 ms; the same
thread at ``SCHED_IDLE`` to 9.0 ms; the node publishing cached frames without rendering left it
at 8.3 ms, and a renderer in a process of its own at ``SCHED_IDLE`` moved it 0.1–0.4 ms.
(MuJoCo's render and read calls release the interpreter lock; what the thread cost the node
was its scheduling and its share of the process, not the lock held while drawing.) The child
runs at ``SCHED_IDLE`` (Linux; else at the lowest nice): it only gets a core that nothing else
of the machine wants. llvmpipe rasterises in the rendering thread itself (``LP_NUM_THREADS``
0, unless set): with one rasteriser thread of its own, each frame crossed between two threads
and often two cores, and took longer (640 × 480 colour + depth p50 8.1–8.4 ms against 7.4–7.9,
side by side on the 2-core machine, the state topics' rows as good or better).

How a frame goes: the parent sends the camera's name and the joint positions of the cycle
(a pickle on a socket pair); the child renders with
:class:`~jaka_driver.sim.camera_render.CameraRenderer` into the camera's place in a shared
memory file (``memfd``) and answers with the time it took; the parent copies the pixels out.
One frame at a time is in flight. The child ends when its socket closes: when the parent
closes it, or when the parent dies.

The child is :func:`serve` in a new interpreter (``sys.executable``, the parent's
``sys.path``), given the file descriptors of its socket and of the memory. Units: m, rad, px, s.
"""
from __future__ import annotations

import dataclasses
import mmap
import os
import socket
import subprocess
import sys
import time
from multiprocessing.connection import Connection
from typing import Optional, Sequence

import numpy as np

from ..common.camera_spec import CameraSpec
from ..common.models import RobotModel
from ..common.sensor_spec import ForceSensorSpec

RASTER_THREADS = 0          # llvmpipe's rasteriser threads (LP_NUM_THREADS), unless set
START_TIMEOUT = 60.0        # s wall for the child to build its model and GL context
CLOSE_TIMEOUT = 2.0         # s wall for the child to end before it is killed
# the child's program (not ``-m`` of this module: its package imports it first)
_CHILD = ("import sys; from jaka_driver.sim.camera_process import serve; "
          "sys.exit(serve(int(sys.argv[1]), int(sys.argv[2])))")


def _layout(cameras: Sequence[CameraSpec]) -> tuple[dict[str, tuple[int, int]], int]:
    """Offset (bytes) of each camera's colour (3 bytes a pixel) and of its depth (4) in the
    shared memory, and the memory's size."""
    out, offset = {}, 0
    for c in cameras:
        pixels = c.width * c.height
        out[c.name] = (offset, offset + 3 * pixels)
        offset += 7 * pixels
    return out, offset


def _views(memory, cameras: Sequence[CameraSpec]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The colour (h, w, 3) uint8 and depth (h, w) float32 arrays of each camera over
    ``memory``."""
    at, _ = _layout(cameras)
    out = {}
    for c in cameras:
        rgb_at, depth_at = at[c.name]
        rgb = np.frombuffer(memory, np.uint8, c.width * c.height * 3, rgb_at)
        depth = np.frombuffer(memory, np.float32, c.width * c.height, depth_at)
        out[c.name] = (rgb.reshape(c.height, c.width, 3), depth.reshape(c.height, c.width))
    return out


class RenderProcess:
    """The renderer of ``cameras`` (as :class:`~jaka_driver.sim.camera_render.CameraRenderer`
    takes them) in a child process. One thread uses it. Raises ``RuntimeError`` with the
    child's words when it cannot start (no EGL, say)."""

    def __init__(self, model: RobotModel, cameras: Sequence[CameraSpec],
                 scene: Optional[str] = None, force_sensor: Optional[ForceSensorSpec] = None,
                 gripper: str = "none"):
        self._cameras = tuple(cameras)
        _, size = _layout(self._cameras)
        memory_fd = os.memfd_create("jaka-cameras")
        ours, theirs = socket.socketpair()
        for end in (ours, theirs):
            end.setblocking(True)       # a default timeout (rospy sets one) makes them not
        try:
            os.ftruncate(memory_fd, size)
            self._memory = mmap.mmap(memory_fd, size)
            env = dict(os.environ)
            env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
            env.setdefault("LP_NUM_THREADS", str(RASTER_THREADS))
            self._child = subprocess.Popen(
                [sys.executable, "-c", _CHILD, str(theirs.fileno()), str(memory_fd)],
                pass_fds=(theirs.fileno(), memory_fd), env=env, stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL)
        finally:
            os.close(memory_fd)
            theirs.close()
        self._conn = Connection(ours.detach())
        self._views = _views(self._memory, self._cameras)
        # io_sizes is a read-only mapping (not picklable); the renderer does not use it
        picklable = dataclasses.replace(model, io_sizes=dict(model.io_sizes))
        try:
            self._conn.send((picklable, self._cameras, scene, force_sensor, gripper))
            if not self._conn.poll(START_TIMEOUT):
                raise RuntimeError(f"the renderer did not start within {START_TIMEOUT:g} s")
            answer = self._conn.recv()
        except (OSError, EOFError) as exc:
            self.close()
            raise RuntimeError(f"the renderer's process ended at start ({exc!r})") from None
        except RuntimeError:
            self.close()
            raise
        if answer != "ready":
            self.close()
            raise RuntimeError(answer)

    @property
    def pid(self) -> int:
        return self._child.pid

    def render(self, name: str, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """(rgb (h, w, 3) uint8, depth (h, w) float32 m — NaN where nothing is seen —, the
        child's seconds of rendering) of camera ``name`` with the twin's joints at ``qpos``.
        Raises ``RuntimeError`` when the child has ended or failed."""
        try:
            self._conn.send((name, np.asarray(qpos, np.float64)))
            answer = self._conn.recv()
        except (OSError, EOFError) as exc:
            code = self._child.poll()
            raise RuntimeError(f"the renderer's process ended (exit code {code}, {exc!r})") \
                from None
        if isinstance(answer, str):
            raise RuntimeError(answer)
        rgb, depth = self._views[name]
        return rgb.copy(), depth.copy(), float(answer)

    def close(self) -> None:
        """End the child (its socket closes; killed if it has not ended within
        :data:`CLOSE_TIMEOUT`). Idempotent."""
        if self._conn is not None:
            self._conn.close()
            self._conn = None
        try:
            self._child.wait(CLOSE_TIMEOUT)
        except subprocess.TimeoutExpired:
            self._child.kill()
            self._child.wait()
        self._views = {}
        try:
            self._memory.close()
        except BufferError:
            pass          # a frame's view is still referenced: the mapping goes with it


def _lowest_priority() -> None:
    """``SCHED_IDLE`` for this process (and the threads it makes from now on), else nice 19."""
    try:
        os.sched_setscheduler(0, os.SCHED_IDLE, os.sched_param(0))
    except (AttributeError, OSError):
        try:
            os.nice(19)
        except OSError:
            pass


def serve(sock_fd: int, memory_fd: int) -> int:
    """The child: renders what the parent asks until its socket closes."""
    _lowest_priority()
    conn = Connection(sock_fd)
    memory = mmap.mmap(memory_fd, 0)
    os.close(memory_fd)
    model, cameras, scene, force_sensor, gripper = conn.recv()
    try:
        from .camera_render import CameraRenderer      # EGL is made here, in the child
        renderer = CameraRenderer(model, cameras, scene, force_sensor, gripper)
    except Exception as exc:  # noqa: BLE001 — said to the parent, which says it to the user
        conn.send(f"offscreen rendering unavailable ({exc!r}); it needs EGL: Debian packages "
                  "libegl1 and libgl1-mesa-dri (make setup)")
        return 1
    views = _views(memory, cameras)
    conn.send("ready")
    try:
        while True:
            try:
                name, qpos = conn.recv()
            except (EOFError, OSError):
                return 0                    # the parent closed its end, or died
            try:
                t0 = time.perf_counter()
                rgb, depth = renderer.render(name, qpos)
                rgb_view, depth_view = views[name]
                rgb_view[...] = rgb
                depth_view[...] = depth
                answer = time.perf_counter() - t0
            except Exception as exc:  # noqa: BLE001 — one bad frame is said, not fatal
                answer = f"rendering camera {name} failed: {exc!r}"
            try:
                conn.send(answer)
            except OSError:
                return 0
    finally:
        renderer.close()

