"""Tool and user frames of a JAKA controller, by id, as the driver knows them.

A controller stores tools and user frames by id — 11 of each, ids 0–10, id 0 being the flange /
the base itself — and answers ``get_tool_offsets`` / ``get_user_offsets`` with the whole table,
row = id, [x, y, z mm, rx, ry, rz deg RPY] (docs/protocol.md, "Frames"). So a frame defined on
the teach pendant can be read back. :class:`ControllerFrames` keeps the driver's copy in a
:class:`~jaka_driver.common.frames.FrameTable`:

* both tables are read at every connection (:meth:`ControllerFrames.read_all`);
* a table is read again, in a thread of its own, when the status stream shows its active id
  change to one this driver did not just activate itself (a frame chosen, and perhaps edited,
  on the pendant);
* what the driver sets (:meth:`ControllerFrames.keep`) is kept at once, before any read;
* an id no table holds (or a table that could not be read) reads as the identity, with one
  warning, and asks for a read.

Frames are 4x4 in metres: tools relative to the flange, user frames relative to the base.
"""
from __future__ import annotations

import logging
import threading
from typing import Callable, Dict, Optional

import numpy as np

from ..common.frames import TOOL, USER_FRAME, FrameTable
from ..common.results import CommandRefused
from ..common.transforms import pose_mm_rpy_to_matrix
from ..protocol import commands

log = logging.getLogger(__name__)

#: Ids a controller's frame tables hold (JAKA's SDK reads ids 0–10 and stores 1–10).
TABLE_SIZE = 11
_REQUESTS = {TOOL: (commands.get_tool_offsets, commands.reply_tool_offsets),
             USER_FRAME: (commands.get_user_offsets, commands.reply_user_offsets)}

#: ``read(request, accessor)`` → the accessor's value; raises CommandRefused (Commander.read).
Reader = Callable[[dict, Callable], object]


class ControllerFrames:
    """The controller's tools and user frames as the driver knows them (thread-safe)."""

    def __init__(self, read: Reader):
        self._read = read
        self.table = FrameTable(on_unknown=self._unknown)
        self._lock = threading.Lock()
        self._known: Dict[str, bool] = {TOOL: False, USER_FRAME: False}   # table read
        self._active: Dict[str, Optional[int]] = {TOOL: None, USER_FRAME: None}
        self._activating: Dict[str, Optional[int]] = {TOOL: None, USER_FRAME: None}
        self._stale = {TOOL: False, USER_FRAME: False}     # a read is wanted
        self._wake = threading.Event()
        self._quit = threading.Event()
        self._thread: Optional[threading.Thread] = None

    # ---- what the backend calls ------------------------------------------------------------
    def read_all(self) -> None:
        """Read both tables now (at a connection: supervisor thread)."""
        for kind in (TOOL, USER_FRAME):
            self._read_table(kind)

    def keep(self, kind: str, frame_id: int, pose: np.ndarray) -> None:
        """The driver stored ``pose`` as ``kind`` ``frame_id`` and is activating it."""
        self.table.store(kind, frame_id, pose)
        self.activating(kind, frame_id)

    def activating(self, kind: str, frame_id: int) -> None:
        """The driver is making ``frame_id`` the active ``kind``: that change is no news."""
        with self._lock:
            self._activating[kind] = int(frame_id)

    def on_active(self, tool_id: int, user_id: int) -> None:
        """The active ids of a status packet (status thread: never blocks). A change the driver
        did not make asks for a read of that table."""
        for kind, frame_id in ((TOOL, tool_id), (USER_FRAME, user_id)):
            with self._lock:
                if self._active[kind] == frame_id:
                    continue
                first = self._active[kind] is None
                self._active[kind] = frame_id
                ours = self._activating[kind] == frame_id
                self._activating[kind] = None
            if not (first or ours):
                log.info("%s %d became active on the controller; reading its offsets", kind,
                         frame_id)
                self._want(kind)

    def describe(self) -> dict:
        return {f"{kind} offsets read from the controller": self._known[kind]
                for kind in (TOOL, USER_FRAME)}

    def stop(self) -> None:
        self._quit.set()
        self._wake.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(2.0)

    # ---- internals -------------------------------------------------------------------------
    def _unknown(self, kind: str, frame_id: int) -> None:
        why = ("no read of the controller's table has succeeded yet" if not self._known[kind]
               else f"the controller's table holds ids 0-{TABLE_SIZE - 1}")
        log.warning("%s %d is active but its offset is unknown (%s): the identity is assumed in "
                    "the driver's conversions until it is read", kind, frame_id, why)
        if not self._known[kind]:
            self._want(kind)

    def _want(self, kind: str) -> None:
        with self._lock:
            self._stale[kind] = True
            if self._thread is None and not self._quit.is_set():
                self._thread = threading.Thread(target=self._run, name="jaka-frames",
                                                daemon=True)
                self._thread.start()
        self._wake.set()

    def _run(self) -> None:
        while not self._quit.is_set():
            self._wake.wait()
            self._wake.clear()
            for kind in (TOOL, USER_FRAME):
                with self._lock:
                    wanted, self._stale[kind] = self._stale[kind], False
                if wanted and not self._quit.is_set():
                    self._read_table(kind)

    def _read_table(self, kind: str) -> None:
        request, accessor = _REQUESTS[kind]
        try:
            rows = self._read(request(), accessor)
        except CommandRefused as refusal:
            log.warning("the controller's %s offsets could not be read (%s); frames defined "
                        "on the teach pendant read as identity until a read succeeds", kind,
                        refusal.message)
            return
        if len(rows) < TABLE_SIZE:
            log.warning("the controller's %s table has %d rows, expected %d (ids 0-%d)", kind,
                        len(rows), TABLE_SIZE, TABLE_SIZE - 1)
        for frame_id, row in enumerate(rows[1:], start=1):   # id 0 is the flange / base
            self.table.store(kind, frame_id, pose_mm_rpy_to_matrix(row))
        self._known[kind] = True
        log.debug("read %d %s offsets from the controller", len(rows), kind)
