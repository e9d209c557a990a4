"""What only a digital twin can do: the one optional capability a backend offers besides the
contract, as :attr:`Backend.twin <jaka_driver.backend.Backend.twin>` (None on a controller).

Who needs it asks the backend for it, never which backend it is: the node offers it under
``~sim/`` (faults, simulated inputs, the snapshot) when it is there, the emulator builds a
controller on it. A request a twin cannot serve is a refused :class:`Result`, as on the contract.

Its parts: the world acting on the arm (an e-stop pressed, a protective stop, an input driven,
a hand pushing the tool);
the camera; what a controller built on the twin reads and drives (the setpoint it commands, the
servo target and its ``stepNum`` ramp, its IO). Commands on the twin's own time (reset, pause,
step) belong here too.

Units as the contract's: joints rad, poses 4x4 in m of the active tool in the active user frame,
speeds m/s. Thread-safe, like the backend.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Dict, Optional, Protocol, Tuple

import numpy as np

from ..common.results import Result
from .robot_state import RobotState

#: (signal "digital"/"analog", IO type, path 0 inputs / 1 outputs) → values, index 0 first
IoSnapshot = Dict[Tuple[str, int, int], list]


class Camera(Protocol):
    """An offscreen camera on the twin's scene."""

    def save(self, q: np.ndarray, path: str) -> str:
        """Render the arm at joints ``q`` (rad) and write a PNG to ``path``; the path written."""


class Twin(ABC):
    """A digital twin's own controls and readings (see the module)."""

    # ---- the world acting on the arm ---------------------------------------------------------
    @abstractmethod
    def press_emergency_stop(self) -> Result:
        """The red button: power is cut, the arm halts on its brakes, servo and drag mode end."""

    @abstractmethod
    def release_emergency_stop(self) -> Result:
        """Release the button; power on and enable to move again."""

    @abstractmethod
    def trigger_protective_stop(self, reason: str = "protective stop (injected)") -> Result:
        """A protective stop, as after a collision: the arm halts; ``clear_error`` recovers."""

    @abstractmethod
    def set_input(self, signal: str, io_type: int, index: int, value: float) -> Result:
        """Drive input ``index`` (from 0) of ``signal`` on ``io_type`` as the outside world
        would (the address already checked against the model)."""

    @abstractmethod
    def push_tool(self, wrench: np.ndarray, duration: float) -> Result:
        """Push the tool with ``wrench`` (Fx Fy Fz N, Mx My Mz N·m along the base's axes, the
        force at the flange centre) for ``duration`` s of the twin's time, as an operator's
        hand would (0 s: let go now); the drives resist it, a force/torque sensor feels it,
        tool drive and admittance follow it."""

    # ---- the twin's own time and state (test suites) -----------------------------------------
    @abstractmethod
    def reset(self, q: Optional[np.ndarray] = None) -> Result:
        """Back to a fresh start at ``q`` (rad, already checked against the limits; None: the
        model's home): the arm at rest there, any motion ended (its waiter told -12), errors
        and the e-stop cleared, powered and enabled, servo and drag mode off, IO at 0, frames,
        payload, collision level and speed ratio at their defaults. The same requests after
        it give the same samples, to the bit, as after a fresh start."""

    @abstractmethod
    def pause(self) -> Result:
        """Stop the twin's time (simulated time only: -9 on the wall clock, which no one
        stops)."""

    @abstractmethod
    def unpause(self) -> Result:
        """Let the twin's time run again."""

    @abstractmethod
    def step(self, cycles: int) -> Result:
        """While paused, run ``cycles`` 8 ms cycles and return once they have run;
        ``Result.value`` is the sim time (s) after them."""

    # ---- the camera ------------------------------------------------------------------------------
    @abstractmethod
    def camera(self, width: int, height: int) -> Camera:
        """An offscreen camera of ``width`` × ``height`` px. Make it in the thread that renders
        with it (its GL context belongs to that thread); raises ImportError or RuntimeError
        where offscreen rendering is unavailable."""

    # ---- what a controller built on the twin reads and drives (the emulator) -----------------------
    @abstractmethod
    def commanded_joints(self) -> np.ndarray:
        """The servo setpoint (rad): where the twin drives the arm this cycle."""

    @abstractmethod
    def commanded_tcp(self) -> np.ndarray:
        """The TCP of :meth:`commanded_joints` (4x4, m)."""

    @property
    @abstractmethod
    def motion_active(self) -> bool:
        """A motion source runs (a move, a jog, a stop decelerating): the live source, not the
        last sample."""

    @abstractmethod
    def servo_goal(self) -> Optional[np.ndarray]:
        """The latest servo target (rad; the end of a ramp), or None outside servo mode."""

    @abstractmethod
    def servo_ramp(self, q_target: np.ndarray, steps: int) -> Result:
        """A servo target (rad) reached over ``steps`` cycles of 8 ms, interpolated linearly
        (1 or fewer: the next cycle); -8 outside servo mode."""

    @abstractmethod
    def io_snapshot(self) -> IoSnapshot:
        """Every IO array as it stands now (digital 0/1, analog V)."""

    @property
    @abstractmethod
    def collision_level(self) -> int:
        """The collision sensitivity level the twin runs with (0 off, 1–4)."""

    @abstractmethod
    def parts(self) -> Dict[str, np.ndarray]:
        """Where the scene's parts are now: name → 4x4 pose (m, base frame); empty without
        parts."""

    @abstractmethod
    def tcp_speed(self, state: RobotState) -> float:
        """Speed (m/s) of the active tool's origin in ``state`` (a sample of this twin)."""
