"""The MuJoCo twin's own controls and readings: :class:`~jaka_driver.backend.Twin` on the parts
of a :class:`~.backend.SimBackend`, which offers it as ``backend.twin``.

A facet of the backend, not a second robot: it acts on the same physics loop, flags, IO board
and collision monitor, each handed to it by the backend that owns them. The faults go through
the flags' events (:class:`~.arm_flags.ArmFlags`: the one place the arm's flags are written),
the reset through the backend's own; nothing here reaches into the backend.
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from ..backend.clock import SimClock, WallClock
from ..backend.robot_state import RobotState
from ..backend.twin import Camera, IoSnapshot, Twin
from ..common.constants import SERVO_CYCLE
from ..common.models import RobotModel
from ..common.results import Code, Result
from ..kinematics import Kinematics
from .arm_flags import ArmFlags
from .collisions import CollisionMonitor
from .io_board import IoBoard
from .motions import servo_target
from .parts import PartPoses
from .physics import PhysicsLoop
from .tool_push import ToolPush

#: s of wall time allowed per stepped cycle before step answers that they did not run
STEP_TIMEOUT_PER_CYCLE = 0.05
CONSUMER_WAIT = 1.0              # s (wall) a reset waits for the consumer to take every sample

#: The active (tool, user frame) as 4x4 poses (m): the backend's ``frames``
Frames = Callable[[], tuple]


class SimTwin(Twin):
    """What only the MuJoCo twin can do (the module says how): on ``model`` in ``scene`` (a
    workcell file, for the camera), its ``clock``, ``physics`` loop, ``flags``, ``io`` board,
    ``collisions`` monitor and the hand that ``push``es the tool; ``kinematics`` at the active
    ``frames()``; ``reset(q)`` the backend's fresh start at joints ``q`` (rad)."""

    def __init__(self, model: RobotModel, clock: SimClock | WallClock, physics: PhysicsLoop,
                 flags: ArmFlags, io: IoBoard, collisions: CollisionMonitor, push: ToolPush,
                 kinematics: Kinematics, frames: Frames,
                 reset: Callable[[np.ndarray], None], *, scene: Optional[str] = None,
                 parts: Optional[PartPoses] = None):
        self._model = model
        self._clock = clock
        self._physics = physics
        self._flags = flags
        self._io = io
        self._collisions = collisions
        self._push = push
        self._kin = kinematics
        self._frames = frames
        self._reset = reset
        self._scene = scene
        self._parts = parts

    # ---- the world acting on the arm ---------------------------------------------------------
    def press_emergency_stop(self) -> Result:
        self._flags.press_emergency_stop()
        return Result.success("emergency stop pressed: power cut")

    def release_emergency_stop(self) -> Result:
        self._flags.release_emergency_stop()
        return Result.success("emergency stop released: power on and enable to move again")

    def trigger_protective_stop(self, reason: str = "protective stop (injected)") -> Result:
        self._flags.trigger_protective_stop(reason)
        return Result.success(reason)

    def set_input(self, signal: str, io_type: int, index: int, value: float) -> Result:
        self._io.write_input(signal, io_type, index, value)
        return Result.success(f"{signal} input {index} of type {io_type} = {value:g}")

    def push_tool(self, wrench: np.ndarray, duration: float) -> Result:
        cycles = max(0, round(float(duration) / SERVO_CYCLE))
        w = np.asarray(wrench, float)
        with self._physics.lock:
            self._push.start(self._physics.d, w, cycles)
        if cycles == 0:
            return Result.success("the tool is let go")
        return Result.success(f"pushing the tool with F ({w[0]:.1f}, {w[1]:.1f}, {w[2]:.1f}) N, "
                              f"M ({w[3]:.2f}, {w[4]:.2f}, {w[5]:.2f}) N·m (base axes) for "
                              f"{cycles * SERVO_CYCLE:.3f} s")

    # ---- the twin's own time and state ---------------------------------------------------------
    def reset(self, q: Optional[np.ndarray] = None) -> Result:
        q = self._model.home.copy() if q is None else np.asarray(q, float).copy()
        if self._clock.simulated:
            # The reset's sample carries the stamp of the one before: a consumer that had not
            # taken that one yet would publish both, one that had would skip the reset's —
            # whichever its thread's timing gave. Caught up first, it always skips it.
            self._clock.wait_consumed(CONSUMER_WAIT)
        self._reset(q)
        return Result.success("twin reset: at rest at "
                              f"[{', '.join(f'{x:.4f}' for x in q)}] rad, no error, defaults")

    def pause(self) -> Result:
        clock = self._clock
        if not clock.simulated:
            return Result.failure(Code.WRONG_MODE, "pause needs simulated time (~sim_time "
                                  "true): the twin on the wall clock cannot stop time")
        clock.pause()
        return Result.success(f"twin paused at sim time {clock.now():.3f} s")

    def unpause(self) -> Result:
        clock = self._clock
        if not clock.simulated:
            return Result.failure(Code.WRONG_MODE, "unpause needs simulated time (~sim_time "
                                  "true)")
        clock.unpause()
        return Result.success(f"twin running from sim time {clock.now():.3f} s")

    def step(self, cycles: int) -> Result:
        clock = self._clock
        if not clock.simulated or not clock.paused:
            return Result.failure(Code.WRONG_MODE, "step needs a paused twin in simulated time "
                                  "(~sim_time true, then pause)")
        if not clock.step(int(cycles), STEP_TIMEOUT_PER_CYCLE * cycles + 1.0):
            return Result.failure(Code.COMMUNICATION_ERROR, f"{cycles} cycles did not run within "
                                  f"{STEP_TIMEOUT_PER_CYCLE * cycles + 1.0:g} s of wall time "
                                  f"(sim time {clock.now():.3f} s)")
        return Result.success(f"stepped {cycles} cycles to sim time {clock.now():.3f} s",
                              clock.now())

    # ---- the camera ------------------------------------------------------------------------------
    def camera(self, width: int, height: int) -> Camera:
        from .snapshot import TwinCamera     # EGL and a visual model: only when asked for
        return TwinCamera(self._model, self._scene, width=width, height=height)

    # ---- what a controller built on the twin reads and drives (the emulator) -----------------------
    def commanded_joints(self) -> np.ndarray:
        return self._physics.servo.setpoint.copy()

    def commanded_tcp(self) -> np.ndarray:
        tool, user = self._frames()
        return self._kin.tcp_pose(self.commanded_joints(), tool, user)

    @property
    def motion_active(self) -> bool:
        return bool(self._physics.motion.active)

    def servo_goal(self) -> Optional[np.ndarray]:
        target = servo_target(self._physics.motion)
        return None if target is None else target.goal

    def servo_ramp(self, q_target: np.ndarray, steps: int) -> Result:
        target = servo_target(self._physics.motion)
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        target.ramp(np.asarray(q_target, float), int(steps))     # 1 or fewer: one cycle
        return Result.success("servo target accepted")

    def io_snapshot(self) -> IoSnapshot:
        return self._io.snapshot()

    @property
    def collision_level(self) -> int:
        return self._collisions.level

    def parts(self) -> dict[str, np.ndarray]:
        if self._parts is None or not self._parts.names:
            return {}
        with self._physics.lock:
            return self._parts.poses(self._physics.d)

    def tcp_speed(self, state: RobotState) -> float:
        tool, _ = self._frames()
        return self._kin.tcp_linear_speed(state.joint_position, state.joint_velocity, tool)
