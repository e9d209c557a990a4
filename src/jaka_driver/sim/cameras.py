"""The twin's cameras (``backend.cameras``, :class:`SimCameras`): frames rendered in a process
of their own from a copy of one cycle's state, so rendering never slows the arm.

**When a frame is due.** Counted in cycles, whatever the clock: camera of rate ``r`` Hz is due
at cycle ``n`` when ``floor(n · cycle · r)`` steps up (at 10 Hz, cycles 13, 25, 38, 50 … of
8 ms): a stepped twin gets the frames its steps produce, a paused one none, the same in every
run. At the end of a due cycle the physics loop's per-cycle hook copies ``qpos`` (the arm and
whatever else moves) with the cycle's stamp and number — a few microseconds, no waiting —
and the renderer renders from that copy, never from a half-stepped state.

**Never slower than the arm.** The cycle hands a copy over and goes on; a thread of the
node hands it to the renderer, a process of its own at the lowest priority
(:mod:`.camera_process`: its own interpreter lock, scheduled only on a core nothing else
wants), and publishes what comes back. Where the machine cannot
render at the asked rate, frames wait at most :data:`MAX_PENDING` deep per camera: the oldest
is dropped, counted (:meth:`SimCameras.stats`) and logged (at most every
:data:`DROP_LOG_PERIOD` s). While a paused twin is stepped (sim time) every frame its steps
produce is kept (up to :data:`MAX_PENDING_STEPPED`) and rendered: a test that steps and then
waits gets them all, the same in every run. Only streaming cameras render (the node streams one while
somebody subscribes); the renderer (a process with a GL context) is started at the first stream.
"""
from __future__ import annotations

import logging
import math
import threading
import time
from collections import deque
from typing import Optional, Sequence

import mujoco
import numpy as np

from ..backend.cameras import CameraFrame, Cameras, CameraStats, Listener
from ..common.camera_spec import CameraSpec
from ..common.models import RobotModel
from ..common.results import Code, Result
from ..common.sensor_spec import ForceSensorSpec
from .camera_process import RenderProcess
from .physics import PhysicsLoop

log = logging.getLogger(__name__)

MAX_PENDING = 2             # frames per camera waiting for the renderer before one is dropped
MAX_PENDING_STEPPED = 1000  # the same while a paused twin is stepped: every frame is kept
DROP_LOG_PERIOD = 5.0       # s wall between two log lines about dropped frames
START_TIMEOUT = 90.0        # s wall the first stream waits for the renderer to exist
STOP_TIMEOUT = 5.0          # s wall a stop waits for the frame being rendered to be handed over
RENDER_TIMES_KEPT = 1000    # recent render times per camera, for stats


def due(cycle_number: int, cycle: float, rate: float) -> bool:
    """A frame of a ``rate`` Hz camera is due at the end of cycle ``cycle_number`` (of
    ``cycle`` s)."""
    return (math.floor(cycle_number * cycle * rate + 1e-9)
            > math.floor((cycle_number - 1) * cycle * rate + 1e-9))


class SimCameras(Cameras):
    """``cameras`` of the twin of ``model`` in ``scene`` (``force_sensor`` as mounted), on the
    physics loop ``physics``; see the module."""

    def __init__(self, cameras: Sequence[CameraSpec], model: RobotModel,
                 scene: Optional[str], physics: PhysicsLoop,
                 force_sensor: Optional[ForceSensorSpec] = None, gripper: str = "none"):
        self._specs = tuple(cameras)
        self._model, self._scene, self._sensor = model, scene, force_sensor
        self._gripper = gripper         # the renderer's model must have the twin's joints
        self._physics = physics
        self._cycle = physics.cycle
        self._cond = threading.Condition()
        self._streaming: dict[str, float] = {}      # name → rate, Hz
        self._pending: deque = deque()              # (name, stamp, cycle number, qpos)
        self._listeners: list[Listener] = []
        self._rendered = {c.name: 0 for c in cameras}
        self._dropped = {c.name: 0 for c in cameras}
        self._times = {c.name: deque(maxlen=RENDER_TIMES_KEPT) for c in cameras}
        self._dropped_since_log = 0
        self._last_drop_log = 0.0
        self._rendering: Optional[str] = None       # the camera whose frame is being made
        self._renderer: Optional[RenderProcess] = None
        self._thread: Optional[threading.Thread] = None
        self._ready = threading.Event()
        self._failure: Optional[str] = None
        self._quit = threading.Event()
        physics.on_cycle.append(self._on_cycle)

    # ---- the facet -----------------------------------------------------------------------------
    @property
    def absent(self) -> Optional[str]:
        return None

    def specs(self) -> tuple[CameraSpec, ...]:
        return self._specs

    def stream(self, name: str, on: bool) -> Result:
        spec = next(c for c in self._specs if c.name == name)
        if not on:
            # Stopped means no frame of it from the answer on: those waiting are forgotten,
            # the one being rendered is handed over first.
            with self._cond:
                self._streaming.pop(name, None)
                for waiting in [p for p in self._pending if p[0] == name]:
                    self._pending.remove(waiting)
                self._cond.wait_for(lambda: self._rendering != name, STOP_TIMEOUT)
            return Result.success(f"camera {name} stopped")
        failure = self._start_renderer()
        if failure is not None:
            return Result.failure(Code.WRONG_MODE, f"camera {name}: {failure}")
        with self._cond:
            self._streaming[name] = spec.rate
        return Result.success(f"camera {name} streams at {spec.rate:g} Hz, "
                              f"{spec.width}x{spec.height} px")

    def listen(self, listener: Listener) -> Result:
        with self._cond:
            self._listeners.append(listener)
        return Result.success("listening to every camera's frames")

    def stats(self, name: str) -> CameraStats:
        with self._cond:
            return CameraStats(name, self._rendered.get(name, 0), self._dropped.get(name, 0),
                               tuple(self._times.get(name, ())))

    @property
    def renderer_pid(self) -> Optional[int]:
        """The rendering process's id while it runs (None before the first stream and once
        the cameras are closed or failed)."""
        renderer = self._renderer
        return renderer.pid if renderer is not None and self._failure is None else None

    def describe(self) -> str:
        """Each camera, what it is asked for and what it did (diagnostics)."""
        with self._cond:
            return "; ".join(
                f"{c.name} {c.width}x{c.height} {c.rate:g} Hz"
                f"{' streaming' if c.name in self._streaming else ''}: "
                f"{self._rendered[c.name]} rendered, {self._dropped[c.name]} dropped"
                for c in self._specs)

    def close(self) -> None:
        self._quit.set()
        with self._cond:
            self._cond.notify_all()
        if self._thread is not None:
            self._thread.join(timeout=2.0)

    # ---- the physics loop's side: a copy at the end of a due cycle ----------------------------
    def _on_cycle(self, d: mujoco.MjData) -> None:
        streaming = self._streaming
        if not streaming:
            return
        n = round(d.time / self._cycle)
        names = [name for name, rate in list(streaming.items()) if due(n, self._cycle, rate)]
        if not names:
            return
        stamp = self._physics.wall0 + d.time        # the sample's stamp of this cycle
        q = d.qpos.copy()
        clock = self._physics.clock
        deep = MAX_PENDING_STEPPED if clock is not None and clock.paused else MAX_PENDING
        with self._cond:
            for name in names:
                waiting = [p for p in self._pending if p[0] == name]
                if len(waiting) >= deep:
                    self._pending.remove(waiting[0])
                    self._dropped[name] += 1
                    self._dropped_since_log += 1
                self._pending.append((name, stamp, n, q))
            self._cond.notify()

    # ---- the thread that feeds the renderer and hands its frames on --------------------------
    def _start_renderer(self) -> Optional[str]:
        """None once the renderer runs, else why it cannot."""
        with self._cond:
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="twin-cameras",
                                                daemon=True)
                self._thread.start()
        if not self._ready.wait(START_TIMEOUT):
            return f"the renderer did not start within {START_TIMEOUT:g} s"
        return self._failure

    def _run(self) -> None:
        # At the default priority, not lower: this thread holds the interpreter lock while it
        # copies a frame and serialises its messages, and a lowered thread that lost its core
        # meanwhile kept the arm's threads waiting for the lock.
        try:
            renderer = RenderProcess(self._model, self._specs, self._scene, self._sensor,
                                     self._gripper)
        except RuntimeError as exc:         # no EGL: every stream says why
            self._failure = str(exc)
            log.error("cameras: %s", self._failure)
            self._ready.set()
            return
        self._renderer = renderer
        self._ready.set()
        try:
            while True:
                with self._cond:
                    while not self._pending and not self._quit.is_set():
                        self._cond.wait(0.5)
                    if self._quit.is_set():
                        return
                    name, stamp, n, q = self._pending.popleft()
                    listeners = list(self._listeners)
                    self._rendering = name
                self._log_drops()
                try:
                    rgb, depth, took = renderer.render(name, q)
                except RuntimeError as exc:
                    self._fail(str(exc))
                    return
                frame = CameraFrame(name, stamp, n, q[:6].copy(), rgb, depth, took)
                with self._cond:
                    self._rendered[name] += 1
                    self._times[name].append(took)
                for listener in listeners:
                    try:
                        listener(frame)
                    except Exception:  # noqa: BLE001 — a listener must not stop the cameras
                        log.exception("camera listener failed")
                with self._cond:
                    self._rendering = None
                    self._cond.notify_all()
        finally:
            self._renderer = None
            renderer.close()

    def _fail(self, why: str) -> None:
        """The renderer cannot go on: every stream ends, and a new one is refused with ``why``."""
        log.error("cameras: %s; every camera stops", why)
        with self._cond:
            self._failure = why
            self._streaming.clear()
            self._pending.clear()
            self._rendering = None
            self._cond.notify_all()

    def _log_drops(self) -> None:
        now = time.monotonic()
        if self._dropped_since_log and now - self._last_drop_log >= DROP_LOG_PERIOD:
            with self._cond:
                dropped, self._dropped_since_log = self._dropped_since_log, 0
                rates = ", ".join(f"{n} {r:g} Hz" for n, r in self._streaming.items())
            times = [t for ts in self._times.values() for t in ts]
            took = f"{1e3 * float(np.median(times)):.0f} ms a frame" if times else "?"
            log.warning("cameras: %d frames dropped: the machine renders slower than asked "
                        "(%s; rendering takes %s)", dropped, rates, took)
            self._last_drop_log = now
