"""JAKA's official ROS 1 node (jaka_driver.cpp), restated for tests as the calls it makes on JAKA's
SDK (:mod:`jaka_sdk_model`): at start-up, in its state loop, and per service (the mapping of
each service to SDK calls is the node's code, as docs/interface.md describes its services).
"""
from __future__ import annotations

import math
import threading
import time
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .jaka_sdk_model import (ABS, COORD_BASE, COORD_JOINT, COORD_TOOL, CONTINUE, INCR, RC_OK,
                              RC_TIMEOUT, JakaSdk)
from .jaka_sdk_status import RobotStatus
from .threads import join_all


def _rotvec_to_rpy(rotvec: Sequence[float]) -> List[float]:
    angle = float(np.linalg.norm(rotvec))
    if angle < 1e-12:
        return [0.0, 0.0, 0.0]
    k = np.asarray(rotvec, float) / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    R = np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K
    return [math.atan2(R[2, 1], R[2, 2]), math.asin(-R[2, 0]), math.atan2(R[1, 0], R[0, 0])]


class JakaRosNode:
    """The calls JAKA's ROS 1 node makes on its SDK: at start-up, in its state loop, and per
    service (docs/interface.md names the services; the mapping is the node's code). A service
    returns the SDK's rc (the node answers ret 1 for 0)."""

    def __init__(self, sdk: JakaSdk, power_wait: float = 8.0, enable_wait: float = 4.0):
        self.sdk = sdk
        self.power_wait, self.enable_wait = power_wait, enable_wait   # the node's sleeps
        self.jog_index: Optional[int] = None
        self.polls = 0
        self.failures: List[BaseException] = []
        self._stop = threading.Event()
        self._poller: Optional[threading.Thread] = None

    def start_up(self) -> Dict[str, str]:
        rc, identity = self.sdk.login_in()
        assert rc == RC_OK, f"login_in: {rc}"
        _, status = self.sdk.get_robot_status()
        if not status.powered_on:
            assert self.sdk.power_on() == RC_OK
            time.sleep(self.power_wait)
        _, status = self.sdk.get_robot_status()
        if not status.enabled:
            assert self.sdk.enable_robot() == RC_OK
            time.sleep(self.enable_wait)
        assert self.sdk.servo_speed_foresight(15, 0.03) == RC_OK
        return identity

    # -- the state loop: robot_states_callback --
    def robot_state(self) -> Tuple[int, RobotStatus]:
        """(motion_state, status) as the node publishes them: 2 e-stop, 4 error, 0 idle, 1
        paused, 3 running."""
        _, status = self.sdk.get_robot_status()
        _, program = self.sdk.get_program_state()
        if status.emergency_stop:
            motion = 2
        elif status.errcode != 0:
            motion = 4
        elif status.inpos and program == 0 and not status.drag_status:
            motion = 0
        elif program == 2:
            motion = 1
        else:
            motion = 3
        return motion, status

    def start_polling(self, period: float = 0.125) -> None:
        """The node's own loop, about 8 times a second, from its own thread, on its own SDK
        connections (a second handle, as the node's status thread has its own reads)."""
        poller = JakaRosNode(JakaSdk(self.sdk.host, self.sdk.command_port, self.sdk.data_port))

        def run() -> None:
            try:
                while not self._stop.wait(period):
                    poller.robot_state()
                    self.polls += 1
            except BaseException as exc:  # noqa: BLE001 - what would kill the node
                self.failures.append(exc)
            finally:
                poller.sdk.close()
        self._poller = threading.Thread(target=run, daemon=True, name="jaka-node-poller")
        self._poller.start()

    def stop_polling(self) -> None:
        """End the loop; fails if its thread is still alive after 5 s (a poll that hangs)."""
        self._stop.set()
        if self._poller is not None:
            join_all([self._poller], 5.0)

    # -- services --
    def linear_move(self, pose: Sequence[float], mvvelo: float, mvacc: float) -> int:
        rc = self.sdk.linear_move(pose, ABS, mvvelo, mvacc, tol=0.5)
        return rc if rc != RC_OK or self.sdk.wait_inpos(30.0) else RC_TIMEOUT

    def joint_move(self, pose: Sequence[float], mvvelo: float, mvacc: float) -> int:
        rc = self.sdk.joint_move(pose, ABS, mvvelo, mvacc, tol=0.5)
        return rc if rc != RC_OK or self.sdk.wait_inpos(30.0) else RC_TIMEOUT

    def jog(self, index: int, coord_mode: int, mvacc: float) -> int:
        """index 0..11 (odd: negative), coord_mode 0 joint, 1 base, 2 tool; the speed is
        mvacc (the node's own reading)."""
        coord = {0: COORD_JOINT, 1: COORD_BASE, 2: COORD_TOOL}[coord_mode]
        if index != self.jog_index:
            self.sdk.motion_abort()
            self.jog_index = index
        velocity = -mvacc if index % 2 else mvacc
        return self.sdk.jog(index // 2, CONTINUE, coord, velocity, 0.0)

    def servo_move_enable(self, on: bool) -> int:
        return self.sdk.servo_move_enable(on)

    def servo_p(self, pose: Sequence[float]) -> int:
        return self.sdk.servo_p(pose, INCR)

    def servo_j(self, pose: Sequence[float]) -> int:
        return self.sdk.servo_j(pose, INCR)

    def stop_move(self) -> int:
        self.jog_index = None
        return self.sdk.motion_abort()

    def set_toolframe(self, tool_num: int, pose: Sequence[float]) -> int:
        """pose: mm + rotation vector rad (flange frame)."""
        frame = list(pose[:3]) + _rotvec_to_rpy(pose[3:])
        return self.sdk.set_tool_data(tool_num, frame, "ToolCoord")

    def set_userframe(self, user_num: int, pose: Sequence[float]) -> int:
        frame = list(pose[:3]) + _rotvec_to_rpy(pose[3:])
        return self.sdk.set_user_frame_data(user_num, frame, "BaseCoord")

    def set_payload(self, tool_num: int, mass: float, xc: float, yc: float, zc: float) -> int:
        rc = self.sdk.set_tool_id(tool_num)
        return rc if rc != RC_OK else self.sdk.set_payload(mass, [xc, yc, zc])

    def drag_move(self, on: bool) -> int:
        return self.sdk.drag_mode_enable(on)

    def set_collisionlevel(self, value: int) -> int:
        level = 1 if value <= 25 else 2 if value <= 50 else 3 if value <= 75 else \
            4 if value <= 100 else 5
        return self.sdk.set_collision_level(level)

    def set_io(self, signal: str, io_type: int, index: int, value: float) -> int:
        if signal == "digital":
            return self.sdk.set_digital_output(io_type, index, value != 0)
        return self.sdk.set_analog_output(io_type, index, value)

    def get_io(self, signal: str, path: int, io_type: int, index: int) -> Tuple[int, float]:
        read = {("digital", 0): self.sdk.get_digital_input,
                ("digital", 1): self.sdk.get_digital_output,
                ("analog", 0): self.sdk.get_analog_input,
                ("analog", 1): self.sdk.get_analog_output}[(signal, path)]
        rc, value = read(io_type, index)
        return rc, float(value)

    def get_fk(self, joints: Sequence[float]) -> Tuple[int, Optional[list]]:
        return self.sdk.kine_forward(joints)

    def get_ik(self, ref_joint: Sequence[float], pose: Sequence[float]):
        return self.sdk.kine_inverse(ref_joint, pose)
