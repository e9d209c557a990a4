"""The MuJoCo twin's own controls and readings: :class:`~jaka_driver.backend.Twin` on a
:class:`~.backend.SimBackend`, which offers it as ``backend.twin``.

A facet of the backend, not a second robot: it acts on the same physics, IO board and controller
flags, under the backend's lock (same package, so it reaches the backend's private parts; nobody
outside reaches them).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Optional

import numpy as np

from ..backend.robot_state import RobotState
from ..backend.twin import Camera, IoSnapshot, Twin
from ..common.constants import SERVO_CYCLE
from ..common.results import Code, Result
from .motions import stopped

#: s of wall time allowed per stepped cycle before step answers that they did not run
STEP_TIMEOUT_PER_CYCLE = 0.05

if TYPE_CHECKING:
    from .backend import SimBackend


class SimTwin(Twin):
    """What only the MuJoCo twin of ``backend`` can do (the module says how)."""

    def __init__(self, backend: "SimBackend"):
        self._b = backend

    # ---- the world acting on the arm ---------------------------------------------------------
    def press_emergency_stop(self) -> Result:
        b = self._b
        with b._lock:
            b._emergency_stop = True
            b._physics.servo.released = False
            b._halt(stopped("stopped: emergency stop"))
            b._powered = b._enabled = b._servo_mode = b._drag_mode = False
        return Result.success("emergency stop pressed: power cut")

    def release_emergency_stop(self) -> Result:
        with self._b._lock:
            self._b._emergency_stop = False
        return Result.success("emergency stop released: power on and enable to move again")

    def trigger_protective_stop(self, reason: str = "protective stop (injected)") -> Result:
        b = self._b
        with b._lock:
            b._protective_stop = True
            b._error_message = reason
            b._halt(stopped(reason))
            b._servo_mode = False
        return Result.success(reason)

    def set_input(self, signal: str, io_type: int, index: int, value: float) -> Result:
        self._b._io.write_input(signal, io_type, index, value)
        return Result.success(f"{signal} input {index} of type {io_type} = {value:g}")

    def push_tool(self, wrench: np.ndarray, duration: float) -> Result:
        b = self._b
        cycles = max(0, round(float(duration) / SERVO_CYCLE))
        w = np.asarray(wrench, float)
        with b._physics.lock:
            b._push.start(b._physics.d, w, cycles)
        if cycles == 0:
            return Result.success("the tool is let go")
        return Result.success(f"pushing the tool with F ({w[0]:.1f}, {w[1]:.1f}, {w[2]:.1f}) N, "
                              f"M ({w[3]:.2f}, {w[4]:.2f}, {w[5]:.2f}) N·m (base axes) for "
                              f"{cycles * SERVO_CYCLE:.3f} s")

    # ---- the twin's own time and state ---------------------------------------------------------
    def reset(self, q: Optional[np.ndarray] = None) -> Result:
        b = self._b
        q = b.model.home.copy() if q is None else np.asarray(q, float).copy()
        b._reset(q)
        return Result.success("twin reset: at rest at "
                              f"[{', '.join(f'{x:.4f}' for x in q)}] rad, no error, defaults")

    def pause(self) -> Result:
        clock = self._b.clock
        if not clock.simulated:
            return Result.failure(Code.WRONG_MODE, "pause needs simulated time (~sim_time "
                                  "true): the twin on the wall clock cannot stop time")
        clock.pause()
        return Result.success(f"twin paused at sim time {clock.now():.3f} s")

    def unpause(self) -> Result:
        clock = self._b.clock
        if not clock.simulated:
            return Result.failure(Code.WRONG_MODE, "unpause needs simulated time (~sim_time "
                                  "true)")
        clock.unpause()
        return Result.success(f"twin running from sim time {clock.now():.3f} s")

    def step(self, cycles: int) -> Result:
        clock = self._b.clock
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
        return TwinCamera(self._b.model, self._b._scene, width=width, height=height)

    # ---- what a controller built on the twin reads and drives (the emulator) -----------------------
    def commanded_joints(self) -> np.ndarray:
        return self._b._physics.servo.setpoint.copy()

    def commanded_tcp(self) -> np.ndarray:
        tool, user = self._b.frames()
        return self._b._kin.tcp_pose(self.commanded_joints(), tool, user)

    @property
    def motion_active(self) -> bool:
        return bool(self._b._physics.motion.active)

    def servo_goal(self) -> Optional[np.ndarray]:
        target = self._b._servo_target()
        return None if target is None else target.goal

    def servo_ramp(self, q_target: np.ndarray, steps: int) -> Result:
        target = self._b._servo_target()
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        target.ramp(np.asarray(q_target, float), int(steps))     # 1 or fewer: one cycle
        return Result.success("servo target accepted")

    def io_snapshot(self) -> IoSnapshot:
        return self._b._io.snapshot()

    @property
    def collision_level(self) -> int:
        return self._b._collision_level

    def tcp_speed(self, state: RobotState) -> float:
        tool, _ = self._b.frames()
        jacobian = self._b._kin.jacobian(state.joint_position, tool)
        return float(np.linalg.norm(jacobian[:3] @ state.joint_velocity))
