"""Moves through the door: joint, linear and circular moves, trajectories and ``stop_move`` —
each checked field by field, planned once (its duration, by the law every backend times it with)
and waited for in the one loop of :meth:`MoveRequests.run_move`, where an overrun or a monitor's
objection stops the arm (docs/design.md, "The backend contract"). A program step's move comes
with the step's :class:`~jaka_driver.programs.executor.MoveHold`: it is paused, resumed and
stopped through it, and the time it stands paused does not count towards its overrun.
"""
from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from ..backend.robot_state import RobotState
from ..common.constants import move_deadline
from ..common.results import Code, Result, invalid
from ..conventions import cartesian
from ..programs.executor import MoveHold
from . import checks as check
from .door import RequestPart, answers, note, with_notes
from .program_steps import PausedTime


class MoveRequests(RequestPart):
    """Moves, trajectories and stop (see the module)."""

    @answers
    def joint_move(self, pose: Sequence[float], mvvelo: float, mvacc: float,
                   mvtime: float = 0.0, hold: MoveHold | None = None) -> Result:
        """Synchronised joint move to ``pose`` (rad) at ``mvvelo`` rad/s, ``mvacc`` rad/s²;
        ``mvtime`` > 0 stretches it to that many seconds. Blocks. ``hold``: a program step's
        pause and stop switch (the step of a running program may move; it is paused and stopped
        through it)."""
        q = check.joint_targets("pose", pose, self.model)
        notes: list[str] = []
        v = check.speed("mvvelo", mvvelo, float(np.max(self.model.max_velocity)), "rad/s",
                        notes=notes)
        a = check.speed("mvacc", mvacc, float(np.max(self.model.max_acceleration)), "rad/s²",
                        default=self.model.default_joint_accel, notes=notes)
        duration = check.finite("mvtime", mvtime, "s")
        if duration < 0:
            raise invalid(f"mvtime is {duration:g} s, expected ≥ 0 (0 = as fast as allowed)")
        planned = check.joint_move_duration(self.backend.state().joint_position, q,
                                            np.minimum(v, self.model.max_velocity),
                                            np.minimum(a, self.model.max_acceleration),
                                            duration or None, mvvelo, mvacc) / self.door.ratio()
        result = self.run_move("joint_move", lambda st: self.backend.start_joint_move(
            q, v, a, planned), hold=hold)
        return with_notes(result, notes)

    @answers
    def linear_move(self, pose: Sequence[float], mvvelo: float, mvacc: float,
                    coord_mode: int = 0, has_ref: bool = False,
                    ref_joint: Sequence[float] = (), hold: MoveHold | None = None) -> Result:
        """Straight-line move to ``pose`` (mm + rotation vector, or RPY with ``jaka_code``
        conventions) at ``mvvelo`` mm/s, ``mvacc`` mm/s²; ``coord_mode`` 0 user frame, 1 base
        frame, 2 relative in the tool frame (``jaka_code``: always 0, no IK seed, as JAKA's
        code passes neither on). Blocks. ``hold``: as :meth:`joint_move`'s."""
        target_mm = check.vector("pose", pose)
        notes: list[str] = []
        if not self.conventions.linear_move_frame_fields:
            if coord_mode or has_ref:
                notes.append(f"coord_mode {coord_mode} and has_ref {bool(has_ref)} not read "
                             f"(conventions {self.conventions.name}: the target is absolute, "
                             "in the active user frame, as JAKA's driver code moves)")
            coord_mode, has_ref = 0, False
        mode = check.integer_in("coord_mode", coord_mode, 0, 2)
        note(notes, cartesian.reading_note(self.conventions, "pose", target_mm))
        # the request's mm: limits and refusals speak its unit, SI from here on
        v = check.speed("mvvelo", mvvelo, self.model.max_tcp_speed * 1000.0, "mm/s",
                        notes=notes) / 1000.0
        a = check.speed("mvacc", mvacc, self.model.max_tcp_accel * 1000.0, "mm/s²",
                        default=self.model.default_tcp_accel * 1000.0, notes=notes) / 1000.0
        ref_q = check.joint_targets("ref_joint", ref_joint, self.model) if has_ref else None

        def start(st: RobotState) -> Result:
            target = cartesian.pose_to_matrix_mm(self.conventions, target_mm)
            if mode == 1:
                _, user = self.backend.frames()
                target = np.linalg.inv(user) @ target
            elif mode == 2:
                target = st.tcp_pose @ target
            planned = check.linear_move_duration(st.tcp_pose, target, v, a, mvvelo,
                                                 mvacc) / self.door.ratio()
            return self.backend.start_linear_move(target, v, a, ref_q, planned)

        return with_notes(self.run_move("linear_move", start, hold=hold), notes)

    @answers
    def circular_move(self, pose_mid: Sequence[float], pose_end: Sequence[float],
                      mvvelo: float, mvacc: float, turns: float = 0.0,
                      attitude_mode: int = 0, coord_mode: int = 0,
                      hold: MoveHold | None = None) -> Result:
        """Arc from the TCP through ``pose_mid`` to ``pose_end`` (mm + rotation vector, or RPY
        with ``jaka_code`` conventions; ``coord_mode`` 0 the active user frame, 1 the base
        frame) at ``mvvelo`` mm/s, ``mvacc`` mm/s² (0: the default), ``turns`` more times
        round and attitude rule ``attitude_mode`` 0–3 (docs/interface.md, "circular_move";
        jaka_driver.motion.circular_path). The whole arc is checked before anything moves.
        Blocks. ``hold``: as :meth:`joint_move`'s."""
        mid_mm, end_mm = check.vector("pose_mid", pose_mid), check.vector("pose_end", pose_end)
        notes: list[str] = []
        # one note is enough: the two poses are read alike
        note(notes, cartesian.reading_note(self.conventions, "pose_mid", mid_mm)
              or cartesian.reading_note(self.conventions, "pose_end", end_mm))
        mode = check.integer_in("coord_mode", coord_mode, 0, 1)
        rule = check.integer_in("attitude_mode", attitude_mode, 0, 3)
        n_turns = check.turns(turns)
        v = check.speed("mvvelo", mvvelo, self.model.max_tcp_speed * 1000.0, "mm/s",
                        notes=notes) / 1000.0
        a = check.speed("mvacc", mvacc, self.model.max_tcp_accel * 1000.0, "mm/s²",
                        default=self.model.default_tcp_accel * 1000.0, notes=notes) / 1000.0

        def start(st: RobotState) -> Result:
            mid, end = (cartesian.pose_to_matrix_mm(self.conventions, p)
                        for p in (mid_mm, end_mm))
            if mode == 1:
                base_to_user = np.linalg.inv(self.backend.frames()[1])
                mid, end = base_to_user @ mid, base_to_user @ end
            planned = check.circular_move_duration(st.tcp_pose, mid, end, v, a, n_turns,
                                                   rule, mvvelo, mvacc) / self.door.ratio()
            return self.backend.start_circular_move(mid, end, v, a, n_turns, rule, planned)

        return with_notes(self.run_move("circular_move", start, hold=hold), notes)

    @answers
    def follow_trajectory(self, trajectory, monitor: Callable[[float, RobotState],
                                                               "str | None"],
                          period: float = 0.02, start_at: float | None = None) -> Result:
        """Execute a planned joint trajectory (FollowJointTrajectory). Every ``period`` s
        (of :attr:`clock`) ``monitor(t, state)`` is called with the time since the start; a
        string it returns aborts: the arm is stopped and the result is -12 with that reason.
        Blocks. At a speed ratio r < 1 the trajectory is played r times as fast in time (a
        controller's servo stream is never scaled by its rate, so the driver scales it, for
        every backend alike) and ``monitor`` still sees the trajectory's own time.
        ``start_at`` (s, the samples' stamps' time: ROS time, the twin's sim time in sim
        time): the trajectory starts then (a goal's ``header.stamp``); the wait is on
        :attr:`clock`, inside this request, so in sim time it starts at exactly that cycle."""
        if start_at is not None:
            self.clock.sleep(start_at - self.backend.state().stamp)
        ratio = self.door.ratio()
        if ratio != 1.0:
            trajectory = trajectory.time_scaled(ratio)
            original = monitor
            monitor = lambda t, st: original(t * ratio, st)     # noqa: E731
        return self.run_move("trajectory", lambda st: self.backend.start_trajectory(trajectory),
                              monitor, period)

    def run_move(self, what: str, start: Callable[[RobotState], Result],
                  monitor: "Callable[[float, RobotState], str | None] | None" = None,
                  period: float = 0.02, hold: MoveHold | None = None) -> Result:
        """The one place a move is waited for: checks the arm may move, ``start(state)`` asks
        the backend to start it (``Result.value`` = completion, planned duration s), then waits
        for the completion. A move still running ``constants.move_deadline(planned)`` s after
        its start, or one ``monitor`` objects to, is stopped and answered -12; a stop_move or
        fault meanwhile finishes the completion with -12 itself. ``hold`` (a program step's)
        pauses the move on its path while it runs, and stops it; the time it stands paused does
        not count towards the deadline."""
        self.door.not_jogging()
        with self.door.blocking_move(what):
            started = start(self.door.ready(program_step=hold is not None))
            if not started.ok:
                return started
            completion, planned = started.value
            deadline = move_deadline(planned)
            clock = self.clock                  # wall time, or the twin's sim time
            paused = PausedTime(clock)
            if hold is not None:         # the backend's own stop: stop_move would stop the
                hold.attach(lambda: paused.began(self.backend.pause_motion()),   # program too
                            lambda: paused.ended(self.backend.resume_motion()),
                            self.backend.stop_move)
            try:
                return self._wait_for(what, completion, planned, deadline, paused, monitor,
                                      period)
            finally:
                if hold is not None:
                    hold.detach()

    def _wait_for(self, what: str, completion, planned: float, deadline: float,
                  paused: PausedTime, monitor, period: float) -> Result:
        clock = self.clock
        t0 = clock.now()
        while True:
            remaining = deadline - (clock.now() - t0 - paused.total())
            # without a monitor there is nothing to do until the move ends or overruns
            wait = min(period, remaining) if monitor is not None else remaining
            result = completion.wait(max(wait, 1e-3), clock)
            if result is not None:
                return result
            elapsed = clock.now() - t0
            reason = monitor(elapsed, self.backend.state()) if monitor else None
            if reason is None and elapsed - paused.total() > deadline:
                reason = (f"{what} not in position {elapsed:.2f} s after its start "
                          f"(planned {planned:.2f} s, allowed {deadline:.2f} s"
                          f"{paused.describe()}); stopped")
            if reason is not None:
                self.backend.stop_move()
                completion.wait(1.0, clock)
                return Result.failure(Code.MOTION_STOPPED, reason)

    @answers
    def stop_move(self) -> Result:
        """Decelerate whatever moves; a blocking move returns -12; a running or paused
        program ends, as a controller's stop does."""
        self.door.forget_jogs()
        if self.backend.programs is not None and self.backend.state().program_state:
            self.backend.programs.stop()
        return self.backend.stop_move()
