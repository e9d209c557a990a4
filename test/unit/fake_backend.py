"""A small in-memory Backend for testing RobotDriver without physics, sockets or ROS: it records
what it was asked, and its moves end when the test says so (``finish_move``) or never."""
from __future__ import annotations

import threading
import time

import numpy as np

from jaka_driver.backend import Backend
from jaka_driver.backend.completion import Completion
from jaka_driver.backend.robot_state import RobotState
from jaka_driver.common.models import load_model
from jaka_driver.common.results import Code, Result

START = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0])


class FakeBackend(Backend):
    """Powered, enabled and at START. ``planned`` (s) is the duration its moves report."""

    def __init__(self, planned: float = 0.05):
        super().__init__(load_model("zu5"))
        self.planned = planned
        self.calls: list[tuple] = []
        self.move: Completion | None = None
        self.q = START.copy()
        self._lock = threading.Lock()

    # -- what a test controls --
    def finish_move(self, result: Result) -> None:
        self.move.finish(result)

    def _started(self, what: str, *args) -> Result:
        with self._lock:
            self.calls.append((what, *args))
            self.move = Completion()
            return Result.success(f"{what} started", (self.move, self.planned))

    def _called(self, what: str, *args) -> Result:
        with self._lock:
            self.calls.append((what, *args))
        return Result.success(what)

    def names(self) -> list[str]:
        return [c[0] for c in self.calls]

    # -- the contract --
    def start(self) -> None:
        pass

    def shutdown(self) -> None:
        pass

    def state(self) -> RobotState:
        return RobotState(stamp=time.time(), joint_position=self.q.copy(), powered=True,
                          enabled=True)

    def wait_for_sample(self, after, timeout):
        return True   # every state() is a new sample, stamped when it is read

    def set_power(self, on):
        return self._called("set_power", on)

    def set_enabled(self, on):
        return self._called("set_enabled", on)

    def start_joint_move(self, q_target, speed, accel, duration=None):
        return self._started("start_joint_move", np.array(q_target), speed, accel, duration)

    def start_linear_move(self, target, speed, accel, ref_q=None, duration=None):
        return self._started("start_linear_move", np.array(target), speed, accel, ref_q,
                             duration)

    def start_trajectory(self, trajectory):
        return self._started("start_trajectory", trajectory)

    def jog(self, coord, axis, direction, speed):
        return self._called("jog", coord, axis, direction, speed)

    def jog_stop(self):
        return self._called("jog_stop")

    def velocity_jog(self, twist, in_tool):
        return self._called("velocity_jog", list(twist), in_tool)

    def set_speed_ratio(self, ratio):
        self.ratio = ratio
        return self._called("set_speed_ratio", ratio)

    def speed_ratio(self):
        return getattr(self, "ratio", 1.0)

    def servo_enable(self, on):
        return self._called("servo_enable", on)

    def servo_j(self, q_target, increment=None):
        return self._called("servo_j", np.array(q_target))

    def servo_p(self, target, increment=None):
        return self._called("servo_p", np.array(target))

    def stop_move(self):
        with self._lock:
            self.calls.append(("stop_move",))
            move = self.move
        if move is not None:
            move.finish(Result.failure(Code.MOTION_STOPPED, "stopped by stop_move"))
        return Result.success("stopping")

    def set_tool_frame(self, tool_id, pose):
        return self._called("set_tool_frame", tool_id, pose)

    def set_user_frame(self, user_id, pose):
        return self._called("set_user_frame", user_id, pose)

    def frames(self):
        return np.eye(4), np.eye(4)

    def set_payload(self, tool_id, mass, centroid):
        return self._called("set_payload", tool_id, mass, centroid)

    def set_drag_mode(self, on):
        return self._called("set_drag_mode", on)

    def set_collision_level(self, level):
        return self._called("set_collision_level", level)

    def set_io(self, signal, io_type, index, value):
        return self._called("set_io", signal, io_type, index, value)

    def get_io(self, signal, path, io_type, index):
        return Result.success("read", 0.0)

    def clear_error(self):
        return self._called("clear_error")

    def forward_kinematics(self, q):
        return Result.success("fk", np.eye(4))

    def inverse_kinematics(self, target, ref_q):
        return Result.success("ik", np.array(ref_q))
