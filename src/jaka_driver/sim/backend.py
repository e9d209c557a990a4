"""The ``sim`` backend: a MuJoCo twin of the arm behind the backend contract.

Powered and enabled at start. Motion is real: planners produce joint trajectories, the
physics thread feeds them to the servo drives every 8 ms, and the state reported is what
MuJoCo computed. Kinematics (FK for the TCP, IK for linear moves, jogs and servo_p) is
Pinocchio on the same URDF.
"""
from __future__ import annotations

import threading
from typing import Optional

import numpy as np

from ..backend import Backend
from ..backend.clock import make_clock
from ..backend.completion import Completion
from ..backend.robot_state import RobotState
from ..common.constants import IN_POSITION, MAX_TOOL_ROTATION_ACCEL, SERVO_CYCLE
from ..common.frames import TOOL, USER_FRAME, FrameTable
from ..common.joint_limits import fastest_step, outside_limits
from ..common.models import RobotModel
from ..common.results import Code, Result
from ..common.transforms import matrix_to_pose_mm
from ..kinematics import Kinematics
from ..motion.linear_path import PlanningError, plan_linear_move
from ..motion.profiles import joint_move_profile
from ..motion.trajectory import JointTrajectory
from . import jog_steps, native_drives
from .collisions import CollisionMonitor
from .io_board import IoBoard
from .motions import Hold, Jog, ServoTarget, Stopping, TrajectoryRun, stopped
from .overload import HOLDING_SHARE, FollowingErrorMonitor, holding_torque, worst_joint
from .physics import PhysicsLoop
from .servo import JointServo
from .twin_model import Payload, build_twin_model

STOP_TIME = 0.15              # s, a stop from full speed takes at most this long


class SimBackend(Backend):
    kind = "sim"

    def __init__(self, model: RobotModel, *, scene: Optional[str] = None,
                 q0: Optional[np.ndarray] = None, io_loopback: bool = False,
                 sim_time: bool = False, real_time_factor: float = 1.0):
        """``sim_time``: the twin owns time (jaka_driver.backend.clock.SimClock, paced at
        ``real_time_factor``, 0 = as fast as possible); otherwise it follows the wall clock."""
        super().__init__(model)
        self.clock = make_clock(sim_time, SERVO_CYCLE, real_time_factor)
        self.kin = Kinematics(model)
        self.mj_model = build_twin_model(model, scene)
        self.scene = scene
        # JAKA's pose_1, unless told otherwise
        q_start = model.home.copy() if q0 is None else np.asarray(q0, float)
        servo = JointServo(self.mj_model, model.servo_kp, model.servo_kd, SERVO_CYCLE,
                           native_drives.load())
        self.physics = PhysicsLoop(self.mj_model, servo, q_start, cycle=SERVO_CYCLE,
                                   clock=self.clock if sim_time else None)
        self.payload = Payload(self.mj_model)
        self.collisions = CollisionMonitor(self.mj_model, self._collided)
        self.overload = FollowingErrorMonitor(servo, model.joint_names, self._overloaded)
        self.physics.on_cycle += [self.collisions.check, self.overload.check]
        self.io = IoBoard(model.io_sizes, loopback=io_loopback)
        self._lock = threading.RLock()
        self.frame_table = FrameTable()
        self.tool_id = 0
        self.user_id = 0
        self.powered = True
        self.enabled = True
        self.servo_mode = False
        self.drag_mode = False
        self.emergency_stop = False
        self.protective_stop = False
        self.collision = False
        self.error_code = 0
        self.error_message = ""
        self.collision_level = 2
        self._stop_decel = np.maximum(model.max_acceleration, model.max_velocity / STOP_TIME)
        self._cache: tuple[tuple, np.ndarray] | None = None

    # ---- life cycle -------------------------------------------------------------------
    def start(self) -> None:
        self.physics.start()

    def shutdown(self) -> None:
        self.physics.stop()

    def describe(self) -> dict:
        info = super().describe()
        info.update(physics_steps=self.physics.steps_total, overruns=self.physics.overruns,
                    timestep_s=self.mj_model.opt.timestep)
        if self.clock.simulated:
            info.update(sim_time_s=f"{self.clock.now():.3f}",
                        real_time_factor=self.clock.real_time_factor or "as fast as possible")
        return info

    def state(self) -> RobotState:
        return self._state_of(self.physics.sample())

    def states_since(self, after: float) -> list[RobotState]:
        return [self._state_of(s) for s in self.physics.samples_since(after)]

    def _state_of(self, sample) -> RobotState:
        tool, user = self.frames()
        # The TCP (Pinocchio FK) is the only costly part: cache it per sample and frame; the
        # flags are read fresh, a mode may change between two physics samples.
        key = (sample.stamp, self.tool_id, self.user_id)
        cached = self._cache
        if cached is not None and cached[0] == key:
            tcp = cached[1]
        else:
            tcp = self.kin.tcp_pose(sample.q, tool, user)
            self._cache = (key, tcp)
        return RobotState(
            stamp=sample.stamp, joint_position=sample.q, joint_velocity=sample.qd,
            joint_effort=sample.tau, tcp_pose=tcp, tool_id=self.tool_id, user_id=self.user_id,
            powered=self.powered, enabled=self.enabled, servo_mode=self.servo_mode,
            drag_mode=self.drag_mode, emergency_stop=self.emergency_stop,
            protective_stop=self.protective_stop, collision=self.collision,
            moving=sample.moving, error_code=self.error_code, error_message=self.error_message)

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        return self.physics.wait_for_sample(after, timeout)

    # ---- power ----------------------------------------------------------------------------
    def set_power(self, on: bool) -> Result:
        with self._lock:
            if not on:
                # Brakes: the arm holds where it is, servo mode and drag end.
                self._halt(stopped("stopped: power off"))
                self.enabled = self.servo_mode = self.drag_mode = False
                self.physics.servo.released = False
            self.powered = on
        return Result.success("powered on" if on else "powered off")

    def set_enabled(self, on: bool) -> Result:
        with self._lock:
            if not on:
                self._halt(stopped("stopped: robot disabled"))
                self.servo_mode = self.drag_mode = False
                self.physics.servo.released = False
            self.enabled = on
        return Result.success("enabled" if on else "disabled")

    def _halt(self, reason: Result) -> None:
        """Halt within one cycle where the arm is; tell a waiting move why."""
        self.physics.hold_here().abort(reason)

    # ---- faults (sim only: /jaka_driver/sim/...) ------------------------------------------------
    def _collided(self, message: str) -> None:
        """Protective stop on a contact above the threshold (runs in the physics thread).

        Contacts are checked once per 8 ms cycle, so the force is seen over the threshold up
        to a cycle after it crossed it; the arm is held where it stood at the end of the
        previous cycle, whose contacts were below the threshold, so it does not stay pressed
        into the obstacle (up to ~2 mm back at a 0.3 m/s swing)."""
        self.collision = True
        self.error_message = message
        self.physics.hold_at(self.physics.checked_pose()).abort(stopped(message))
        self.servo_mode = False

    def _overloaded(self, message: str) -> None:
        """Protective stop on brakes when a drive cannot hold (runs in the physics thread)."""
        self.protective_stop = True
        self.error_message = message
        self.physics.engage_brakes().abort(stopped(message))
        self.servo_mode = False

    def _cannot_hold(self, mass: float, centroid: np.ndarray, share: float) -> Optional[str]:
        """Why the drives could not hold the arm still here with this payload (None if they
        can): the joint, the torque it needs and its limit."""
        with self.physics.lock:
            tau = holding_torque(self.mj_model, self.physics.d.qpos[:6].copy(), self.payload,
                                 mass, centroid)
        k, used = worst_joint(tau, self.model.max_effort)
        if used <= share:
            return None
        limit = self.model.max_effort[k]
        return (f"holding the arm here needs {self.model.joint_names[k]} {abs(tau[k]):.1f} N·m, "
                f"above {share * limit:.1f} N·m ({share * 100:.0f} % of its {limit:g} N·m limit)")

    def press_emergency_stop(self) -> Result:
        """The red button: power is cut, the arm halts on its brakes."""
        with self._lock:
            self.emergency_stop = True
            self.physics.servo.released = False
            self._halt(stopped("stopped: emergency stop"))
            self.powered = self.enabled = self.servo_mode = self.drag_mode = False
        return Result.success("emergency stop pressed: power cut")

    def release_emergency_stop(self) -> Result:
        with self._lock:
            self.emergency_stop = False
        return Result.success("emergency stop released: power on and enable to move again")

    def trigger_protective_stop(self, reason: str = "protective stop (injected)") -> Result:
        with self._lock:
            self.protective_stop = True
            self.error_message = reason
            self._halt(stopped(reason))
            self.servo_mode = False
        return Result.success(reason)

    def set_input(self, signal: str, io_type: int, index: int, value: float) -> Result:
        """Drive an input as the outside world would."""
        self.io.write_input(signal, io_type, index, value)
        return Result.success(f"{signal} input {index} of type {io_type} = {value:g}")

    # ---- motion ---------------------------------------------------------------------------------
    def _start_run(self, trajectory: JointTrajectory, label: str) -> Result:
        """Hand a planned trajectory to the physics thread; ``Result.value`` is the
        :class:`Completion` to wait on (the emulator replies at once, like a controller)."""
        completion = Completion()
        run = TrajectoryRun(trajectory, SERVO_CYCLE, IN_POSITION, label, completion)
        with self._lock:
            if self.physics.motion.active:
                return Result.failure(Code.BUSY, f"{label} refused: the arm is still moving "
                                      "(stopping)")
            if trajectory.duration == 0:
                completion.finish(Result.success(f"{label}: already in position"))
            else:
                self.physics.switch(run)
        return Result.success(f"{label} started", (completion, trajectory.duration))

    def start_joint_move(self, q_target, speed, accel, duration=None) -> Result:
        """Plan the synchronised profile from the servo setpoint, taking ``duration`` (the
        driver's plan), and hand it to the physics thread."""
        q0 = self.physics.servo.setpoint.copy()
        v = np.minimum(speed, self.model.max_velocity)
        a = np.minimum(accel, self.model.max_acceleration)
        try:
            profile = joint_move_profile(q0, q_target, v, a, duration)
        except ValueError as exc:
            return Result.failure(Code.INVALID_PARAMETER, str(exc))
        return self._start_run(JointTrajectory.from_profile(profile, SERVO_CYCLE), "joint_move")

    def start_linear_move(self, target, speed, accel, ref_q=None, duration=None) -> Result:
        """Plan the whole line (IK at every cycle, limits, speeds) before anything moves, then
        hand it to the physics thread. The line is timed by the law the driver planned
        ``duration`` with, from the setpoint's TCP, and sampled every cycle."""
        tool, user = self.frames()
        q0 = self.physics.servo.setpoint.copy()
        start = self.kin.tcp_pose(q0, tool, user)

        def ik(pose, seed):
            solution = self.kin.ik(pose, seed=seed, tool=tool, user=user)
            return solution.q if solution.success else None

        try:
            trajectory = plan_linear_move(start, target, speed, accel, q0, ik, self.model.lower,
                                          self.model.upper, self.model.max_velocity,
                                          cycle=SERVO_CYCLE, ref_q=ref_q)
        except PlanningError as exc:
            return Result.failure(exc.code, str(exc))
        return self._start_run(trajectory, "linear_move")

    def start_trajectory(self, trajectory: JointTrajectory) -> Result:
        return self._start_run(trajectory, "trajectory")

    def jog(self, coord, axis, direction, speed) -> Result:
        with self._lock:
            current = self.physics.motion
            label = (coord, axis, direction)
            if isinstance(current, Jog) and current.active and current.label == label:
                current.command(speed)
                return Result.success("jogging")
            if current.active and not isinstance(current, Jog):
                return Result.failure(Code.BUSY, "jog refused: the arm is moving")
            jog = self._make_jog(coord, axis, direction, speed)
            if isinstance(current, Jog) and current.active:
                # Switching direction: brake the old axis first, then start the new one.
                self.physics.switch(Stopping(self._stop_decel, SERVO_CYCLE,
                                             on_rest=lambda: self.physics.switch(jog)))
            else:
                self.physics.switch(jog)
        return Result.success("jogging")

    def _make_jog(self, coord, axis, direction, speed) -> Jog:
        jog: Jog
        if coord == 0:
            accel = float(self.model.max_acceleration[axis])
            step = jog_steps.joint_step(self.model, axis, direction, lambda: jog.stop(), accel,
                                        SERVO_CYCLE)
        else:
            accel = self.model.max_tcp_accel if axis < 3 else MAX_TOOL_ROTATION_ACCEL
            tool, _ = self.frames()
            step = jog_steps.cartesian_step(self.kin, self.model, axis, direction, coord == 2,
                                            tool, SERVO_CYCLE)
        jog = Jog(speed, accel, SERVO_CYCLE, step, (coord, axis, direction))
        return jog

    def jog_stop(self) -> Result:
        with self._lock:
            current = self.physics.motion
            if isinstance(current, Jog) and current.active:
                current.stop()
        return Result.success("jog stopping")

    def servo_enable(self, on: bool) -> Result:
        with self._lock:
            if on == self.servo_mode:
                return Result.success(f"servo mode already {'on' if on else 'off'}")
            if on:
                if self.physics.motion.active:
                    return Result.failure(Code.BUSY, "servo mode refused: the arm is moving")
                # Ramped: also serves the emulator's servo_j with stepNum (servo_ramp).
                self.physics.switch(ServoTarget(self.physics.servo.setpoint, self.physics))
            else:
                self.physics.switch(Hold())
            self.servo_mode = on
        return Result.success(f"servo mode {'on' if on else 'off'}")

    def _servo_target(self) -> Optional[ServoTarget]:
        motion = self.physics.motion
        return motion if isinstance(motion, ServoTarget) else None

    def servo_j(self, q_target) -> Result:
        target = self._servo_target()
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        target.set(np.asarray(q_target, float))
        self.clock.streamed()
        return Result.success("servo_j target accepted")

    def servo_p(self, target_pose) -> Result:
        target = self._servo_target()
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        tool, user = self.frames()
        seed = target.latest
        solution = self.kin.ik(target_pose, seed=seed, tool=tool, user=user)
        if not solution.success:
            return Result.failure(Code.IK_FAILED, f"servo_p target has no IK solution near the "
                                  f"current joints: {solution.message}")
        q = solution.q
        i = outside_limits(self.model, q)
        if i is not None:
            return Result.failure(Code.IK_FAILED, f"servo_p target needs "
                                  f"{self.model.joint_names[i]} = {q[i]:.3f} rad, outside its "
                                  "limits")
        too_fast = fastest_step(self.model, seed, q)
        if too_fast is not None:
            j, speed = too_fast
            return Result.failure(Code.INVALID_PARAMETER, f"servo_p target needs "
                                  f"{self.model.joint_names[j]} at {speed:.2f} rad/s, "
                                  f"limit {self.model.max_velocity[j]:.2f} rad/s; the arm "
                                  "holds")
        target.set(q)
        self.clock.streamed()
        return Result.success("servo_p target accepted", q)

    def stop_move(self) -> Result:
        with self._lock:
            current = self.physics.motion
            if isinstance(current, ServoTarget):
                current.hold(self.physics.servo.setpoint)
                return Result.success("servo target held where the arm is")
            if not current.active:
                return Result.success("nothing was moving")
            self._stop_motion(stopped("stopped by stop_move"))
        return Result.success("stopping")

    def _stop_motion(self, reason: Result) -> None:
        with self._lock:
            self.physics.switch(Stopping(self._stop_decel, SERVO_CYCLE)).abort(reason)

    # ---- what a controller built on the twin reads and drives (the emulator) ------------------
    # A narrow public section: the emulator uses these and the Backend contract, never
    # ``physics`` or ``kin`` directly. Joints rad, poses 4x4 in metres (active tool, user frame).
    def commanded_joints(self) -> np.ndarray:
        """The servo setpoint (rad): where the twin is driving the arm this cycle."""
        return self.physics.servo.setpoint.copy()

    def commanded_tcp(self) -> np.ndarray:
        """The TCP of :meth:`commanded_joints` (4x4, m)."""
        tool, user = self.frames()
        return self.kin.tcp_pose(self.commanded_joints(), tool, user)

    @property
    def motion_active(self) -> bool:
        """A motion source is running (a move, jog, or a stop decelerating); the live source,
        not the last physics sample."""
        return bool(self.physics.motion.active)

    def servo_goal(self) -> Optional[np.ndarray]:
        """The latest servo target (rad, the end of a ramp), or None outside servo mode."""
        target = self._servo_target()
        return None if target is None else target.goal

    def servo_ramp(self, q_target, steps: int) -> Result:
        """servo_j reached over ``steps`` cycles (8 ms each), interpolated linearly."""
        target = self._servo_target()
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        target.ramp(np.asarray(q_target, float), int(steps))     # 1 or fewer: one cycle
        return Result.success("servo target accepted")

    # ---- frames, payload, settings ---------------------------------------------------------------
    def frames(self):
        with self._lock:
            return self.frame_table.active(self.tool_id, self.user_id)

    def set_tool_frame(self, tool_id, pose) -> Result:
        with self._lock:
            self.frame_table.store(TOOL, tool_id, pose)
            self.tool_id = tool_id
        return Result.success(f"tool {tool_id} set {_mm(pose)} and active")

    def set_user_frame(self, user_id, pose) -> Result:
        with self._lock:
            self.frame_table.store(USER_FRAME, user_id, pose)
            self.user_id = user_id
        return Result.success(f"user frame {user_id} set {_mm(pose)} and active")

    def set_payload(self, tool_id, mass, centroid) -> Result:
        why = self._cannot_hold(mass, centroid, HOLDING_SHARE)
        if why is not None:
            c = np.linalg.norm(centroid) * 1000
            return Result.failure(Code.INVALID_PARAMETER, f"mass {mass:g} kg with its centroid "
                                  f"{c:.0f} mm from the flange: {why}; lighter payload or "
                                  "centroid nearer the flange")
        with self._lock:
            with self.physics.lock:
                self.payload.set(mass, centroid)
            self.tool_id = tool_id
        c = centroid * 1000
        return Result.success(f"payload {mass:g} kg at ({c[0]:.1f}, {c[1]:.1f}, {c[2]:.1f}) mm "
                              f"on the flange; tool {tool_id} active")

    def set_drag_mode(self, on: bool) -> Result:
        with self._lock:
            if on == self.drag_mode:
                return Result.success(f"drag mode already {'on' if on else 'off'}")
            if on:
                if self.servo_mode:
                    return Result.failure(Code.WRONG_MODE, "drag mode refused in servo mode")
                if self.physics.motion.active:
                    return Result.failure(Code.BUSY, "drag mode refused while the arm moves")
                self.physics.switch(Hold())
                self.physics.servo.released = True
            else:
                with self.physics.lock:
                    self.physics.servo.released = False
                    self.physics.hold_here()
            self.drag_mode = on
        return Result.success(f"drag mode {'on' if on else 'off'}")

    def set_collision_level(self, level) -> Result:
        with self._lock:
            self.collision_level = self.collisions.level = level
        if level == 0:
            return Result.success("collision detection off")
        return Result.success(f"collision level {level} ({25 * level} N)")

    def set_io(self, signal, io_type, index, value) -> Result:
        self.io.write_output(signal, io_type, index, value)
        return Result.success(f"{signal} output {index} of type {io_type} = {value:g}")

    def get_io(self, signal, path, io_type, index) -> Result:
        value = self.io.read(signal, path, io_type, index)
        return Result.success(f"{signal} {'output' if path else 'input'} {index} of type "
                              f"{io_type} = {value:g}", value)

    def clear_error(self) -> Result:
        with self._lock:
            if self.physics.braked:
                # Opening the brakes on an arm the drives cannot hold would drop it.
                why = self._cannot_hold(self.payload.mass, self.payload.centroid, 1.0)
                if why is not None:
                    return Result.failure(Code.MOTION_STOPPED, f"the protective stop stands: "
                                          f"{why}; set a lighter payload first")
                self.physics.release_brakes()
            self.overload.rearm()
            was = [name for name, flag in (("collision", self.collision),
                                           ("protective stop", self.protective_stop),
                                           ("error", self.error_code != 0)) if flag]
            self.collision = self.protective_stop = False
            self.error_code, self.error_message = 0, ""
            self.collisions.armed = True
        return Result.success(f"cleared {', '.join(was)}" if was else "no error to clear")

    # ---- kinematics -------------------------------------------------------------------------------------
    def forward_kinematics(self, q) -> Result:
        tool, user = self.frames()
        return Result.success("forward kinematics of the active tool in the active user frame",
                              self.kin.tcp_pose(np.asarray(q, float), tool, user))

    def inverse_kinematics(self, target, ref_q) -> Result:
        tool, user = self.frames()
        solution = self.kin.ik(target, seed=np.asarray(ref_q, float), tool=tool, user=user)
        if not solution.success:
            return Result.failure(Code.IK_FAILED, f"no IK solution: {solution.message}")
        q = solution.q
        if outside_limits(self.model, q) is not None:
            return Result.failure(Code.IK_FAILED, "the IK solution leaves the joint limits")
        return Result.success("inverse kinematics nearest ref_joint", q)


def _mm(pose: np.ndarray) -> str:
    p = matrix_to_pose_mm(pose)
    return f"to ({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm, ({p[3]:.4f}, {p[4]:.4f}, {p[5]:.4f}) rad"
