"""Pictures of the twin as it stands now, for ``~sim/snapshot`` (:mod:`.twin_services`): a PNG,
800 × 600 px, from the twin's camera (``driver.twin.camera``).

A picture takes ~0.1 s of CPU in Mesa's software rasteriser. It is made in one worker thread at
a lower scheduling priority (Mesa's own threads inherit it) so that the 125 Hz state publisher
wins the CPU when both want it (measured on 2 cores: 125 Hz kept through 30 back-to-back
pictures). The camera (a GL context) is created on the first call: a node that never takes a
picture never pays for it.
"""
from __future__ import annotations

import os
import queue
import threading

import rospy

from ..driver import RobotDriver

RENDER_NICE = 10            # nice increment of the render thread (Linux: per thread)
RENDER_TIMEOUT = 30.0       # s a call waits for its picture, first call included
WIDTH, HEIGHT = 800, 600    # px


def default_path() -> str:
    """``$ROS_HOME/<node name>_snapshot.png``: two drivers in two namespaces do not overwrite
    each other's picture."""
    home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    stem = rospy.get_name().strip("/").replace("/", "_") or "jaka_driver"
    return os.path.join(home, f"{stem}_snapshot.png")


class SnapshotWorker:
    """Renders pictures of the arm in its own thread, one at a time: the driver's camera (the
    twin's), the joints of ``driver.state()``."""

    def __init__(self, driver: RobotDriver):
        self._driver = driver
        self._requests: queue.Queue = queue.Queue()
        self._camera = None
        threading.Thread(target=self._run, name="twin-snapshot", daemon=True).start()

    def take(self, path: str, timeout: float = RENDER_TIMEOUT) -> tuple[bool, str]:
        """Write the current pose to ``path``; (success, message). The joints are read when
        the worker gets to the request, so the picture is at most one render old."""
        done: queue.Queue = queue.Queue(maxsize=1)
        self._requests.put((path, done))
        try:
            return done.get(timeout=timeout)
        except queue.Empty:
            return False, f"no picture within {timeout:g} s (renderer busy or stuck)"

    def _run(self) -> None:
        try:
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), RENDER_NICE)
        except (OSError, AttributeError):
            pass   # not Linux, or not allowed: pictures still work, just at full priority
        while True:
            path, done = self._requests.get()
            done.put(self._render(path))

    def _render(self, path: str) -> tuple[bool, str]:
        try:
            if self._camera is None:
                self._camera = self._driver.twin.camera(WIDTH, HEIGHT)
            q = self._driver.state().joint_position
            written = self._camera.save(q, path)
        except (ImportError, RuntimeError) as exc:
            return False, (f"offscreen rendering unavailable ({exc}); it needs EGL: Debian "
                           "packages libegl1 and libgl1-mesa-dri (make setup)")
        except (OSError, ValueError) as exc:
            return False, f"no picture written to {path}: {exc}"
        joints = ", ".join(f"{v:.4f}" for v in q)
        return True, (f"{written} ({WIDTH}x{HEIGHT} px): {self._driver.model.name} at "
                      f"[{joints}] rad")
