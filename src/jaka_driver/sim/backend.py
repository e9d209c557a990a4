"""The ``sim`` backend: a MuJoCo twin of the arm behind the backend contract.

Powered and enabled at start. Motion is real: planners produce joint trajectories, the
physics thread feeds them to the servo drives every 8 ms, and the state reported is what
MuJoCo computed. Kinematics (FK for the TCP, IK for linear moves, jogs and servo_p) is
Pinocchio on the same URDF.

Its face is the contract, ``twin`` (:class:`.twin.SimTwin`: faults, inputs, the camera,
what the emulator reads and drives), ``force`` (:class:`.force.SimForce` when the arm
carries a force/torque sensor), ``programs``, ``recording`` (:class:`.recording.
SimRecording`, trajectory recording into the programs folder) and ``cameras``
(:class:`.cameras.SimCameras` when the scene or ``wrist_camera`` gives it any); everything else
is private. The motion that runs now has one
owner, the physics loop's slot (:attr:`.physics.PhysicsLoop.motion`: switched, aborted, stopped
there); the arm's flags have one, :class:`.arm_flags.ArmFlags`, which the twin's faults and the
force sensor's stops use too.
"""
from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np

from ..backend import Backend
from ..backend.cameras import HOW_TO_ADD, NoCameras
from ..backend.clock import make_clock
from ..backend.completion import Completion
from ..backend.force import HOW_TO_MOUNT, NoForceSensor
from ..backend.programs import NoPrograms, Programs
from ..backend.robot_state import RobotState
from ..common.camera_spec import cameras_of_scene
from ..common.constants import IN_POSITION, MAX_TOOL_ROTATION_ACCEL, SERVO_CYCLE
from ..common.frames import TOOL, USER_FRAME, FrameTable
from ..common.installation import Installation
from ..common.joint_limits import fastest_step, on_limit, outside_limits
from ..common.models import RobotModel
from ..common.results import Code, Result
from ..common.transforms import matrix_to_pose_mm
from ..kinematics import Kinematics
from ..motion import velocity_jog
from ..motion.cartesian_path import PlanningError
from ..motion.circular_path import plan_circular_move
from ..motion.linear_path import plan_linear_move
from ..motion.profiles import joint_move_profile
from ..motion.servo_filters import FilterType, ServoFilterSpec, make_filter
from ..motion.trajectory import JointTrajectory
from ..motion.velocity_jog import VelocityJog
from . import jog_steps, native_drives
from .arm_flags import ArmFlags
from .cameras import SimCameras
from .collisions import CollisionMonitor
from .force import SimForce
from .ft_sensor import TOOL_BODY
from .gripper import DhGripper
from .io_board import IoBoard
from .tool_connector import SimToolIO
from .motions import (Hold, Jog, ServoTarget, Stopping, TrajectoryRun, TwistRun, servo_target,
                      stopped)
from .overload import HOLDING_SHARE, FollowingErrorMonitor, holding_torque, worst_joint
from .parts import PartPoses, part_names
from .physics import PhysicsLoop
from .recording import SimRecording
from .servo import JointServo
from .suction import SuctionCup
from .tool_push import ToolPush
from .twin import SimTwin
from .twin_model import FLANGE_BODY, Payload, build_twin_model

STOP_TIME = 0.15              # s, a stop from full speed takes at most this long


class _Status(NamedTuple):
    """What a sample reports beside the physics (:class:`RobotState`'s fields of the same
    names; ``tool``, ``user`` the active frames, 4x4 m), read when the sample is recorded:
    a sample published any number of cycles later still says what stood at its stamp, so the
    stream is the same whenever its reader gets a core."""

    tool_id: int
    user_id: int
    tool: np.ndarray
    user: np.ndarray
    powered: bool
    enabled: bool
    servo_mode: bool
    drag_mode: bool
    emergency_stop: bool
    protective_stop: bool
    collision: bool
    error_code: int
    error_message: str
    program_state: int
    io: object


class SimBackend(Backend):
    """The MuJoCo twin of ``model`` (see the module); ``scene`` a workcell file, ``q0`` the
    start joints (rad; default the model's home), ``io_loopback`` wires each output to the
    input of the same index, ``force_sensor`` mounts (True) or removes (False) the flange
    force/torque sensor of the model's configuration (None: as configured), ``gripper`` mounts
    a tool after it: ``none``, ``dh_pgi`` (the DH gripper, :mod:`.gripper`) or ``suction``
    (:mod:`.suction`), a device on the tool connector (``tool_device``)."""

    def __init__(self, model: RobotModel, *, scene: Optional[str] = None,
                 q0: Optional[np.ndarray] = None, io_loopback: bool = False,
                 sim_time: bool = False, real_time_factor: float = 1.0,
                 programs: Optional[Programs] = None, force_sensor: Optional[bool] = None,
                 gripper: str = "none", wrist_camera: bool = False):
        """``sim_time``: the twin owns time (jaka_driver.backend.clock.SimClock, paced at
        ``real_time_factor``, 0 = as fast as possible); otherwise it follows the wall clock.
        ``programs``: the program engine the twin runs (a
        :class:`jaka_driver.programs.FolderPrograms`, docs/programs.md), handed in by whoever
        builds the twin; None: the twin has no programs (:class:`NoPrograms`).
        Cameras: the ``scene`` file's ``cameras:`` and, with ``wrist_camera``, the default
        wrist camera (jaka_driver.common.camera_spec; ValueError if one is wrong)."""
        cameras = cameras_of_scene(scene, wrist_camera)     # refused before anything is built
        super().__init__(model)
        self.clock = make_clock(sim_time, SERVO_CYCLE, real_time_factor)
        self.programs = programs if programs is not None else NoPrograms(
            "no programs on this twin (the node's ~programs parameter, launch argument "
            "programs)")
        self._kin = Kinematics(model)
        sensor = model.force_sensor.mounted_as(force_sensor)
        self._mj_model = build_twin_model(model, scene, force_sensor=sensor, gripper=gripper)
        # JAKA's pose_1, unless told otherwise
        q_start = model.home.copy() if q0 is None else np.asarray(q0, float)
        servo = JointServo(self._mj_model, model.servo_kp, model.servo_kd, SERVO_CYCLE,
                           native_drives.load())
        self._physics = PhysicsLoop(self._mj_model, servo, q_start, cycle=SERVO_CYCLE,
                                   clock=self.clock if sim_time else None)
        self._flags = ArmFlags(self._physics)
        #: the tool on the tool connector (None: no tool), a ToolDevice (sim/tool_device.py)
        self.tool_device = {"none": lambda m, d: None, "dh_pgi": DhGripper,
                            "suction": SuctionCup}[gripper](self._mj_model, self._physics.d)
        self.gripper = gripper
        self._lock = self._flags.lock       # the flags, and the motion a mode allows, together
        tool_body = TOOL_BODY if sensor.mounted else FLANGE_BODY
        self._payload = Payload(self._mj_model, tool_body)
        self._push = ToolPush(self._mj_model, tool_body)
        self._collisions = CollisionMonitor(self._mj_model, self._flags.collided)
        self._overload = FollowingErrorMonitor(servo, model.joint_names, self._flags.overloaded)
        self._physics.on_cycle += [self._collisions.check, self._overload.check,
                                   self._push.apply]
        if sensor.mounted:
            self.force = SimForce(sensor, model, self.clock, self._physics, self._flags,
                                  self._kin, self.frames, self._velocity_jog)
            self._physics.on_cycle.append(self.force.check)
            self._physics.force_reading = lambda: self.force.readings.latest
        else:
            self.force = NoForceSensor(f"no force/torque sensor on this arm ({HOW_TO_MOUNT})")
        if cameras:
            self.cameras = SimCameras(cameras, model, scene, self._physics, sensor, gripper)
        else:
            self.cameras = NoCameras(f"no camera on this twin ({HOW_TO_ADD})")
        self._io = IoBoard(model.io_sizes, loopback=io_loopback)
        self.tool_io = SimToolIO(self._io, self._physics.lock)
        self._physics.on_cycle.append(self.tool_io.on_cycle)
        self.tool_io.attach(self.tool_device)       # for good: a reset keeps it on the connector
        self._mounting = Installation()     # upright: MuJoCo's default gravity, −z
        self._defaults()
        # trajectory recording: the tool's pose offered every cycle, after the checks
        self.recording = SimRecording(self.programs.folder, self._kin, self.frames,
                                      lambda: (self._tool_id, self._user_id),
                                      self._physics,
                                      model.max_tcp_speed, model.max_tcp_accel)
        self._physics.on_cycle.append(self.recording.sample)
        self._stop_decel = np.maximum(model.max_acceleration, model.max_velocity / STOP_TIME)
        self._cache: tuple | None = None    # (sample, tool, user, its TCP, on a limit)
        self.twin = SimTwin(model, self.clock, self._physics, self._flags, self._io,
                            self._collisions, self._push, self._kin, self.frames, self._reset,
                            scene=scene, parts=PartPoses(self._mj_model, part_names(scene)))
        self._physics.status_reading = self._status

    def _defaults(self) -> None:
        """The controller's state of a fresh twin: powered, enabled, no error (the flags'),
        default frames, collision level 2, full speed."""
        self._flags.reset()
        self._frame_table = FrameTable()
        self._tool_id = 0
        self._user_id = 0
        self._collisions.level = 2
        self._collisions.armed = True
        self._speed_ratio = 1.0
        self._servo_filter = ServoFilterSpec()

    def _reset(self, q: np.ndarray) -> None:
        """Back to a fresh start at ``q`` (rad): :class:`.twin.SimTwin`'s reset."""
        self.programs.reset()             # first: a program's step would act on the reset arm
        self.recording.reset()            # what was recorded before the reset is kept
        with self._lock:
            with self._physics.lock:
                self._physics.servo.released = False
                self._payload.reset()           # first: the reset's forward pass uses the model
                if isinstance(self.force, SimForce):
                    self.force.reset()          # before the reset's sample: no reading yet
                self._physics.reset(q).abort(stopped("stopped: the twin was reset"))
                self._push.start(self._physics.d, np.zeros(6), 0)
                if self.tool_device is not None:
                    self.tool_device.reset()    # as mounted: the fingers limp, nothing held
                # in the same pause of the cycles: no cycle polls the fresh device through the
                # old settings; the connector's reset tells the device the supply is off
                self._io.reset()
                self.tool_io.reset()
            self._overload.rearm()
            self._defaults()
            self._cache = None

    # ---- life cycle -------------------------------------------------------------------
    def start(self) -> None:
        self._physics.start()

    def shutdown(self) -> None:
        self._physics.stop()
        if isinstance(self.cameras, SimCameras):
            self.cameras.close()

    def describe(self) -> dict:
        info = {"backend": "sim", **super().describe()}
        info.update(physics_steps=self._physics.steps_total, overruns=self._physics.overruns,
                    timestep_s=self._mj_model.opt.timestep,
                    servo_filter=self._servo_filter.describe(),
                    force_sensor="none" if self.force.absent else "flange",
                    tool=self.gripper)
        if isinstance(self.cameras, SimCameras):
            info.update(cameras=self.cameras.describe())
        if self.clock.simulated:
            info.update(sim_time_s=f"{self.clock.now():.3f}",
                        real_time_factor=self.clock.real_time_factor or "as fast as possible")
        return info

    def state(self) -> RobotState:
        """The latest sample with the flags, modes and IO as they stand now (a request that
        changed one a moment ago sees it, before the next cycle)."""
        return self._state_of(self._physics.sample(), self._status())

    def states_since(self, after: float) -> list[RobotState]:
        """Each sample with the flags, modes and IO recorded with it."""
        return [self._state_of(s, s.status or self._status())
                for s in self._physics.samples_since(after)]

    def _status(self) -> _Status:
        """The flags, modes, frames and IO now. Read without the flags' lock: the physics
        thread calls it with its own lock held, which a request holding the flags' lock may be
        waiting for; in sim time nothing changes them while a cycle is recorded."""
        f = self._flags
        tool_id, user_id = self._tool_id, self._user_id
        tool, user = self._frame_table.shared(tool_id, user_id)
        return _Status(tool_id, user_id, tool, user, f.powered, f.enabled, f.servo_mode,
                       f.drag_mode, f.emergency_stop, f.protective_stop, f.collision,
                       f.error_code, f.error_message, int(self.programs.state_now()),
                       self._io.values())

    def _state_of(self, sample, status: _Status) -> RobotState:
        # What follows from the joints alone — the TCP (Pinocchio FK) and whether a joint is on
        # its limit — is computed once per sample and frames: a request reads the state a few
        # times (the emulator's servo_j up to three), each a read of the same cycle. The key is by
        # identity: the sample itself, not its stamp (a reset in sim time records a new sample
        # with the stamp of the one before), and the frames as the table keeps them (the same
        # arrays until one is stored again: FrameTable.shared).
        cached = self._cache
        if (cached is not None and cached[0] is sample and cached[1] is status.tool
                and cached[2] is status.user):
            tcp, limit = cached[3], cached[4]
        else:
            tcp = self._kin.tcp_pose(sample.q, status.tool, status.user)
            limit = on_limit(self.model, sample.q)
            self._cache = (sample, status.tool, status.user, tcp, limit)
        return RobotState(
            stamp=sample.stamp, joint_position=sample.q, joint_velocity=sample.qd,
            joint_effort=sample.tau, tcp_pose=tcp, tool_id=status.tool_id,
            user_id=status.user_id, powered=status.powered, enabled=status.enabled,
            servo_mode=status.servo_mode, drag_mode=status.drag_mode,
            emergency_stop=status.emergency_stop, protective_stop=status.protective_stop,
            collision=status.collision, moving=sample.moving, error_code=status.error_code,
            error_message=status.error_message, program_state=status.program_state,
            io=status.io, force=sample.force,
            on_limit=limit)

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        return self._physics.wait_for_sample(after, timeout)

    # ---- power ----------------------------------------------------------------------------
    def set_power(self, on: bool) -> Result:
        self._flags.power(on)
        return Result.success("powered on" if on else "powered off")

    def set_enabled(self, on: bool) -> Result:
        self._flags.enable(on)
        return Result.success("enabled" if on else "disabled")

    def _cannot_hold(self, mass: float, centroid: np.ndarray, share: float) -> Optional[str]:
        """Why the drives could not hold the arm still here with this payload (None if they
        can): the joint, the torque it needs and its limit."""
        with self._physics.lock:
            tau = holding_torque(self._mj_model, self._physics.d.qpos[:6].copy(), self._payload,
                                 mass, centroid)
        k, used = worst_joint(tau, self.model.max_effort)
        if used <= share:
            return None
        limit = self.model.max_effort[k]
        return (f"holding the arm here needs {self.model.joint_names[k]} {abs(tau[k]):.1f} N·m, "
                f"above {share * limit:.1f} N·m ({share * 100:.0f} % of its {limit:g} N·m limit)")

    # ---- motion ---------------------------------------------------------------------------------
    def _start_run(self, trajectory: JointTrajectory, label: str) -> Result:
        """Hand a planned trajectory to the physics thread; ``Result.value`` is the
        :class:`Completion` to wait on (the emulator replies at once, like a controller)."""
        completion = Completion()
        run = TrajectoryRun(trajectory, SERVO_CYCLE, IN_POSITION, label, completion,
                            accel=self.model.max_acceleration)
        with self._lock:
            if self._physics.motion.active:
                return Result.failure(Code.BUSY, f"{label} refused: "
                                      f"{self._physics.motion.busy_reason}")
            if trajectory.duration == 0:
                completion.finish(Result.success(f"{label}: already in position"))
            else:
                self._physics.switch(run)
        return Result.success(f"{label} started", (completion, trajectory.duration))

    def start_joint_move(self, q_target, speed, accel, duration=None) -> Result:
        """Plan the synchronised profile from the servo setpoint, taking ``duration`` (the
        driver's plan), and hand it to the physics thread."""
        q0 = self._physics.servo.setpoint.copy()
        r = self._speed_ratio               # time scaled by 1/r: speeds × r, accelerations × r²
        v = np.minimum(speed, self.model.max_velocity) * r
        a = np.minimum(accel, self.model.max_acceleration) * r * r
        try:
            profile = joint_move_profile(q0, q_target, v, a, duration)
        except ValueError as exc:
            return Result.failure(Code.INVALID_PARAMETER, str(exc))
        return self._start_run(JointTrajectory.from_profile(profile, SERVO_CYCLE), "joint_move")

    def start_linear_move(self, target, speed, accel, ref_q=None, duration=None) -> Result:
        """Plan the whole line (IK at every cycle, limits, speeds) before anything moves, then
        hand it to the physics thread. The line is timed by the law the driver planned
        ``duration`` with, from the setpoint's TCP, at the speed ratio, and sampled every
        cycle."""
        m = self.model
        return self._start_cartesian("linear_move", lambda start, q0, ik, r: plan_linear_move(
            start, target, speed * r, accel * r * r, q0, ik, m.lower, m.upper, m.max_velocity,
            cycle=SERVO_CYCLE, ref_q=ref_q))

    def start_circular_move(self, mid, end, speed, accel, turns=0.0, mode=0,
                            duration=None) -> Result:
        """The exact arc (:mod:`jaka_driver.motion.circular_path`), planned and checked like a
        line and played the same way."""
        m = self.model
        return self._start_cartesian("circular_move", lambda start, q0, ik, r:
                                     plan_circular_move(start, mid, end, speed * r,
                                                        accel * r * r, q0, ik, m.lower,
                                                        m.upper, m.max_velocity, turns, mode,
                                                        cycle=SERVO_CYCLE))

    def _start_cartesian(self, label: str, plan) -> Result:
        """Plan a Cartesian move from the setpoint's TCP — ``plan(start pose, start joints,
        ik, speed ratio)`` (time scaled by 1/r: speeds × r, accelerations × r²) — and hand it to
        the physics thread; a path that cannot be followed is refused before anything moves."""
        tool, user = self.frames()
        q0 = self._physics.servo.setpoint.copy()

        def ik(pose, seed):
            solution = self._kin.ik(pose, seed=seed, tool=tool, user=user)
            return solution.q if solution.success else None

        try:
            trajectory = plan(self._kin.tcp_pose(q0, tool, user), q0, ik, self._speed_ratio)
        except PlanningError as exc:
            return Result.failure(exc.code, str(exc))
        return self._start_run(trajectory, label)

    def pause_motion(self) -> Result:
        return self._pause_run(True)

    def resume_motion(self) -> Result:
        return self._pause_run(False)

    def _pause_run(self, pause: bool) -> Result:
        """Slow the running planned move to rest on its path, or bring it back to speed."""
        with self._lock:
            run = self._physics.motion
            if not (isinstance(run, TrajectoryRun) and run.active):
                return Result.success(f"no move to {'pause' if pause else 'resume'}")
            run.pause() if pause else run.resume()
        return Result.success(f"{run.label} {'pausing on its path' if pause else 'resumed'}")

    def start_trajectory(self, trajectory: JointTrajectory) -> Result:
        return self._start_run(trajectory, "trajectory")

    def jog(self, coord, axis, direction, speed) -> Result:
        speed = speed * self._speed_ratio
        with self._lock:
            current = self._physics.motion
            label = (coord, axis, direction)
            if isinstance(current, Jog) and current.active and current.label == label:
                current.command(speed)
                return Result.success("jogging")
            if current.active and not isinstance(current, Jog):
                return Result.failure(Code.BUSY, "jog refused: the arm is moving")
            jog = self._make_jog(coord, axis, direction, speed)
            if isinstance(current, Jog) and current.active:
                # Switching direction: brake the old axis first, then start the new one.
                self._physics.switch(Stopping(self._stop_decel, SERVO_CYCLE,
                                             on_rest=lambda: self._physics.switch(jog)))
            else:
                self._physics.switch(jog)
        return Result.success("jogging")

    def _make_jog(self, coord, axis, direction, speed) -> Jog:
        jog: Jog
        ratio_squared = self._speed_ratio ** 2     # the jog's ramp, scaled in time as moves
        if coord == 0:
            accel = float(self.model.max_acceleration[axis]) * ratio_squared
            step = jog_steps.joint_step(self.model, axis, direction, lambda: jog.stop(), accel,
                                        SERVO_CYCLE)
        else:
            accel = (self.model.max_tcp_accel if axis < 3 else MAX_TOOL_ROTATION_ACCEL) \
                * ratio_squared
            tool, _ = self.frames()
            step = jog_steps.cartesian_step(self._kin, self.model, axis, direction, coord == 2,
                                            tool, SERVO_CYCLE)
        jog = Jog(speed, accel, SERVO_CYCLE, step, (coord, axis, direction))
        return jog

    def jog_stop(self) -> Result:
        with self._lock:
            current = self._physics.motion
            if isinstance(current, (Jog, TwistRun)) and current.active:
                current.stop()
        return Result.success("jog stopping")

    def velocity_jog(self, twist, in_tool) -> Result:
        """A velocity jog (:mod:`jaka_driver.motion.velocity_jog`) run by the physics thread,
        at the speed ratio (twist × r, its ramp's accelerations × r²)."""
        twist = np.asarray(twist, float) * self._speed_ratio
        with self._lock:
            current = self._physics.motion
            if isinstance(current, TwistRun) and current.active and current.jog.in_tool == in_tool:
                current.command(twist)
                return current.jog.progress()
            if current.active and not isinstance(current, (Jog, TwistRun)):
                return Result.failure(Code.BUSY, "velocity jog refused: the arm is moving")
            run = TwistRun(self._velocity_jog(in_tool))
            run.command(twist)
            if current.active:
                # another jog, or the other frame: brake it first, then follow the twist
                self._physics.switch(Stopping(self._stop_decel, SERVO_CYCLE,
                                             on_rest=lambda: self._physics.switch(run)))
            else:
                self._physics.switch(run)
        return run.jog.progress()

    def _velocity_jog(self, in_tool: bool) -> VelocityJog:
        tool, _ = self.frames()
        return velocity_jog.on_arm(self._kin, self.model, tool, in_tool=in_tool,
                                   ratio=self._speed_ratio, cycle=SERVO_CYCLE,
                                   angular_accel=MAX_TOOL_ROTATION_ACCEL)

    def set_speed_ratio(self, ratio: float) -> Result:
        with self._lock:
            self._speed_ratio = float(ratio)
        return Result.success(f"speed ratio {ratio:g}: moves and jogs at {ratio * 100:g} % "
                              "speed")

    def speed_ratio(self) -> float:
        return self._speed_ratio

    def servo_enable(self, on: bool) -> Result:
        with self._lock:
            if on == self._flags.servo_mode:
                return Result.success(f"servo mode already {'on' if on else 'off'}")
            if on:
                if self._physics.motion.active:
                    return Result.failure(Code.BUSY, "servo mode refused: the arm is moving")
                # Ramped: also serves the emulator's servo_j with stepNum (servo_ramp).
                self._physics.switch(ServoTarget(self._physics.servo.setpoint, self._physics,
                                                 self._make_servo_filter()))
            else:
                self._physics.switch(Hold())
            self._flags.set_servo_mode(on)
        return Result.success(f"servo mode {'on' if on else 'off'}")

    def set_servo_filter(self, spec: ServoFilterSpec) -> Result:
        """The filter servo targets pass through each cycle from the next servo mode on
        (jaka_driver.motion.servo_filters)."""
        with self._lock:
            if self._flags.servo_mode:
                return Result.failure(Code.WRONG_MODE, "servo filter refused in servo mode: "
                                      "leave it first (servo_move_enable false)")
            self._servo_filter = spec
        return Result.success(f"servo filter {spec.describe()}, from the next servo mode on")

    def _make_servo_filter(self):
        spec = self._servo_filter
        if spec.type == FilterType.NONE:
            return None
        tool, user = self.frames()
        kin = self._kin

        def ik(pose, seed):
            solution = kin.ik(pose, seed=seed, tool=tool, user=user)
            return solution.q if solution.success else None
        return make_filter(spec, SERVO_CYCLE, ik, lambda q: kin.tcp_pose(q, tool, user))

    def servo_j(self, q_target, increment=None) -> Result:
        # the twin's drives follow absolute targets: an increment's target is already here
        target = servo_target(self._physics.motion)
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        target.set(np.asarray(q_target, float))
        self.clock.streamed()
        return Result.success("servo_j target accepted")

    def servo_p(self, target_pose, increment=None) -> Result:
        target = servo_target(self._physics.motion)
        if target is None:
            return Result.failure(Code.SERVO_MODE_OFF, "servo mode is off")
        tool, user = self.frames()
        seed = target.latest
        solution = self._kin.ik(target_pose, seed=seed, tool=tool, user=user)
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
        target.set(q, np.asarray(target_pose, float))
        self.clock.streamed()
        return Result.success("servo_p target accepted", q)

    def stop_move(self) -> Result:
        with self._lock:
            current = self._physics.motion
            if isinstance(current, ServoTarget):
                current.hold(self._physics.servo.setpoint)
                return Result.success("servo target held where the arm is")
            if not current.active:
                return Result.success("nothing was moving")
            self._stop_motion(stopped("stopped by stop_move"))
        return Result.success("stopping")

    def _stop_motion(self, reason: Result) -> None:
        with self._lock:
            self._physics.switch(Stopping(self._stop_decel, SERVO_CYCLE)).abort(reason)

    # ---- frames, payload, settings ---------------------------------------------------------------
    def frames(self):
        with self._lock:
            return self._frame_table.active(self._tool_id, self._user_id)

    def set_tool_frame(self, tool_id, pose) -> Result:
        with self._lock:
            self._frame_table.store(TOOL, tool_id, pose)
            self._tool_id = tool_id
        return Result.success(f"tool {tool_id} set {_mm(pose)} and active")

    def set_user_frame(self, user_id, pose) -> Result:
        with self._lock:
            self._frame_table.store(USER_FRAME, user_id, pose)
            self._user_id = user_id
        return Result.success(f"user frame {user_id} set {_mm(pose)} and active")

    def set_payload(self, tool_id, mass, centroid) -> Result:
        why = self._cannot_hold(mass, centroid, HOLDING_SHARE)
        if why is not None:
            c = np.linalg.norm(centroid) * 1000
            return Result.failure(Code.INVALID_PARAMETER, f"mass {mass:g} kg with its centroid "
                                  f"{c:.0f} mm from the flange: {why}; lighter payload or "
                                  "centroid nearer the flange")
        with self._lock:
            with self._physics.lock:
                self._payload.set(mass, centroid)
            self._tool_id = tool_id
        c = centroid * 1000
        return Result.success(f"payload {mass:g} kg at ({c[0]:.1f}, {c[1]:.1f}, {c[2]:.1f}) mm "
                              f"on the flange; tool {tool_id} active")

    def set_drag_mode(self, on: bool) -> Result:
        with self._lock:
            if on == self._flags.drag_mode:
                return Result.success(f"drag mode already {'on' if on else 'off'}")
            if on:
                if self._flags.servo_mode:
                    return Result.failure(Code.WRONG_MODE, "drag mode refused in servo mode")
                if self._physics.motion.active:
                    return Result.failure(Code.BUSY, "drag mode refused while the arm moves")
                self._physics.switch(Hold())
                self._physics.servo.released = True
            else:
                with self._physics.lock:
                    self._physics.servo.released = False
                    self._physics.hold_here()
            self._flags.set_drag_mode(on)
        return Result.success(f"drag mode {'on' if on else 'off'}")

    def collision_level(self) -> Result:
        level = int(self._collisions.level)
        return Result.success("collision detection off" if level == 0 else
                              f"collision level {level} ({25 * level} N)", level)

    def set_installation_angle(self, mounting: Installation) -> Result:
        """MuJoCo's gravity turned into the base frame (the base stays the frame of every
        pose, and the floor the surface the base stands on): drives, brakes, payload checks,
        drag mode and the sensor all feel it from the next cycle. Kept through a reset (the
        arm's mounting is the cell's, not a setting)."""
        with self._lock:
            with self._physics.lock:
                self._mj_model.opt.gravity[:] = mounting.gravity
                self._mounting = mounting
        return Result.success(f"installation angle set: {mounting.describe()}; gravity in the "
                              f"base frame {np.round(mounting.gravity, 3).tolist()} m/s²")

    def installation_angle(self) -> Result:
        mounting = self._mounting
        return Result.success(mounting.describe(), mounting)

    def set_collision_level(self, level) -> Result:
        with self._lock:
            self._collisions.level = level
        if level == 0:
            return Result.success("collision detection off")
        return Result.success(f"collision level {level} ({25 * level} N)")

    def set_io(self, signal, io_type, index, value) -> Result:
        self._io.write_output(signal, io_type, index, value)
        return Result.success(f"{signal} output {index} of type {io_type} = {value:g}")

    def get_io(self, signal, path, io_type, index) -> Result:
        value = self._io.read(signal, path, io_type, index)
        return Result.success(f"{signal} {'output' if path else 'input'} {index} of type "
                              f"{io_type} = {value:g}", value)

    def clear_error(self) -> Result:
        with self._lock:
            if self._physics.braked:
                # Opening the brakes on an arm the drives cannot hold would drop it.
                why = self._cannot_hold(self._payload.mass, self._payload.centroid, 1.0)
                if why is not None:
                    return Result.failure(Code.MOTION_STOPPED, f"the protective stop stands: "
                                          f"{why}; set a lighter payload first")
                self._physics.release_brakes()
            self._overload.rearm()
            was = self._flags.clear()
            self._collisions.armed = True
        return Result.success(f"cleared {', '.join(was)}" if was else "no error to clear")

    # ---- kinematics -------------------------------------------------------------------------------------
    def forward_kinematics(self, q) -> Result:
        tool, user = self.frames()
        return Result.success("forward kinematics of the active tool in the active user frame",
                              self._kin.tcp_pose(np.asarray(q, float), tool, user))

    def inverse_kinematics(self, target, ref_q) -> Result:
        tool, user = self.frames()
        solution = self._kin.ik(target, seed=np.asarray(ref_q, float), tool=tool, user=user)
        if not solution.success:
            return Result.failure(Code.IK_FAILED, f"no IK solution: {solution.message}")
        q = solution.q
        if outside_limits(self.model, q) is not None:
            return Result.failure(Code.IK_FAILED, "the IK solution leaves the joint limits")
        return Result.success("inverse kinematics nearest ref_joint", q)


def _mm(pose: np.ndarray) -> str:
    p = matrix_to_pose_mm(pose)
    return f"to ({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm, ({p[3]:.4f}, {p[4]:.4f}, {p[5]:.4f}) rad"
