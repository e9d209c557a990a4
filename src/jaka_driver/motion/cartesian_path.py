"""The whole-path check of a Cartesian move (``linear_move``, ``circular_move``): a TCP path,
already sampled every cycle, followed in joint space before anything moves — IK at every
sample, joint limits, joint speeds, no joint jump (docs/interface.md, "linear_move").

Frames and units: TCP poses are 4x4 homogeneous matrices in one frame (whatever frame ``ik``
expects), positions in metres; joints rad and rad/s, time s. Messages give positions in mm,
the driver's unit.

Kinematics is injected: ``ik(T, seed) -> q or None`` returns the joint solution nearest
``seed`` (rad) or None when there is none.
"""
from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np

from ..common.results import Code, CommandRefused
from .profiles import TrapezoidProfile
from .trajectory import JointTrajectory

# Joint speed and limit checks forgive this much float noise.
_SPEED_RTOL = 1e-9
_LIMIT_TOL = 1e-9                   # rad

IK = Callable[[np.ndarray, np.ndarray], Optional[np.ndarray]]


class PlanningError(CommandRefused):
    """A Cartesian move cannot be planned. ``code`` is -4 (:attr:`Code.IK_FAILED`: unreachable,
    singular, or a joint limit on the path) or -2 (:attr:`Code.INVALID_PARAMETER`); the message
    says what failed, where on the path, and the limit."""


def invalid(message: str) -> PlanningError:
    return PlanningError(Code.INVALID_PARAMETER, message)


def positive(name: str, value: float, unit: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise invalid(f"{name} is {value:g} {unit}, expected a finite value > 0")
    return value


def pose(name: str, T) -> np.ndarray:
    """``T`` as a finite 4x4 homogeneous matrix with a proper rotation (-2 otherwise)."""
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise invalid(f"{name} must be a finite 4x4 homogeneous matrix, got shape {T.shape}")
    R = T[:3, :3]
    if np.max(np.abs(R.T @ R - np.eye(3))) > 1e-6 or np.linalg.det(R) <= 0.0:
        raise invalid(f"{name} has a rotation part that is not a proper rotation matrix")
    return T


def _joints(name: str, value, n: int) -> np.ndarray:
    vec = np.asarray(value, dtype=float)
    if vec.shape != (n,) or not np.all(np.isfinite(vec)):
        raise invalid(f"{name} must be {n} finite values, got shape {vec.shape}")
    return vec


class JointBounds:
    """The arm a path is followed on: where it stands (``q_start``, rad), its position limits
    (``lower``, ``upper``, rad), its speed limits (``v_max``, rad/s) and the optional IK seed of
    the first sample (``ref_q``, rad) — checked once, as every planner takes them."""

    def __init__(self, q_start, lower, upper, v_max, ref_q=None):
        q_start = np.asarray(q_start, dtype=float)
        if q_start.ndim != 1 or q_start.shape[0] == 0:
            raise invalid(f"q_start must be a 1-D array of joint angles, got shape "
                          f"{q_start.shape}")
        n = q_start.shape[0]
        self.n = n
        self.q_start = _joints("q_start", q_start, n)
        self.lower, self.upper = _joints("lower", lower, n), _joints("upper", upper, n)
        self.v_max = _joints("v_max", v_max, n)
        if np.any(self.v_max <= 0.0):
            raise invalid(f"v_max must be > 0 for every joint, got {self.v_max.tolist()}")
        self.ref_q = None if ref_q is None else _joints("ref_q", ref_q, n)


def follow_tcp_path(times: np.ndarray, tcp: np.ndarray, u: np.ndarray, ik: IK,
                    arm: JointBounds, what: str = "path") -> JointTrajectory:
    """The joint motion that puts the TCP at ``tcp[k]`` (N, 4, 4) at ``times[k]`` (N,) s.

    Sample 0 is ``arm.q_start`` itself (the arm is there; solving IK for it would only add
    error). Each further sample is solved by ``ik`` seeded with the previous solution — the
    first with ``arm.ref_q`` when given — and checked: a solution exists, it lies within the
    limits, and no joint moves faster than ``arm.v_max`` since the previous sample; a
    configuration flip or a singularity shows up as such a jump. ``u`` (N,) is each sample's
    share of the path (0–1), for the messages (``what`` names the path in them).

    Returns a :class:`JointTrajectory` with ``qd`` from finite differences (0 at both ends,
    where the TCP is at rest) and the planned ``tcp`` poses. Raises :class:`PlanningError`
    (-4) at the first sample that fails.
    """
    n = arm.n
    q = np.empty((times.shape[0], n))
    q[0] = arm.q_start
    for k in range(1, times.shape[0]):
        first = k == 1 and arm.ref_q is not None
        seed = arm.ref_q if first else q[k - 1]
        q[k] = _solve(ik, tcp[k], seed, n, u[k], what)
        _check_limits(q[k], arm.lower, arm.upper, u[k], what)
        _check_speed(q[k] - q[k - 1], times[k] - times[k - 1], arm.v_max, u[k], what, first)
    qd = np.gradient(q, times, axis=0)
    qd[0] = qd[-1] = 0.0
    return JointTrajectory(times=times, q=q, qd=qd, tcp=tcp)


def _where(u: float, what: str) -> str:
    return f"{100.0 * u:.1f} % of the {what}"


def _solve(ik: IK, T: np.ndarray, seed: np.ndarray, n: int, u: float, what: str) -> np.ndarray:
    solution = ik(T, seed.copy())
    if solution is not None:
        solution = np.asarray(solution, dtype=float)
        if solution.shape != (n,):
            raise ValueError(f"ik returned shape {solution.shape}, expected ({n},)")
    if solution is None or not np.all(np.isfinite(solution)):
        x, y, z = 1000.0 * T[:3, 3]
        raise PlanningError(Code.IK_FAILED, f"no IK solution at {_where(u, what)} "
                            f"(x={x:.1f}, y={y:.1f}, z={z:.1f} mm)")
    return solution


def _check_limits(q: np.ndarray, lower: np.ndarray, upper: np.ndarray, u: float,
                  what: str) -> None:
    excess = np.maximum(lower - q, q - upper)
    i = int(np.argmax(excess))
    if excess[i] > _LIMIT_TOL:
        raise PlanningError(Code.IK_FAILED, f"joint_{i + 1} would leave its limits at "
                            f"{_where(u, what)}: {q[i]:.3f} rad is outside "
                            f"[{lower[i]:.2f}, {upper[i]:.2f}]")


def _check_speed(step: np.ndarray, dt: float, v_max: np.ndarray, u: float, what: str,
                 first: bool) -> None:
    needed = np.abs(step) / dt
    ratio = needed / v_max
    i = int(np.argmax(ratio))
    if ratio[i] > 1.0 + _SPEED_RTOL:
        cause = "ref_joint selects another configuration than the arm's?" if first \
            else "singularity?"
        raise PlanningError(Code.IK_FAILED, f"joint_{i + 1} would need {needed[i]:.2f} rad/s "
                            f"at {_where(u, what)}, limit {v_max[i]:.2f} rad/s ({cause})")


# Translations and rotations below these are "no motion" (float noise of an FK round trip).
ZERO_LENGTH = 1e-12                 # m
ZERO_ANGLE = 1e-12                  # rad


def path_time_law(length: float, angle: float, speed: float, accel: float,
                  angular_speed: float, angular_accel: float) -> Optional[TrapezoidProfile]:
    """The time law of a path parameter u ∈ [0, 1] along a path of ``length`` (m) that turns
    the tool by ``angle`` (rad), or None when there is nothing to move. A unit of u is the
    whole length and the whole angle: u's speed and acceleration limits are the tighter of
    the translation's (``speed`` m/s, ``accel`` m/s²) and the rotation's (``angular_speed``
    rad/s, ``angular_accel`` rad/s²)."""
    if length <= ZERO_LENGTH and angle <= ZERO_ANGLE:
        return None
    u_speed = min(speed / length if length > ZERO_LENGTH else math.inf,
                  angular_speed / angle if angle > ZERO_ANGLE else math.inf)
    u_accel = min(accel / length if length > ZERO_LENGTH else math.inf,
                  angular_accel / angle if angle > ZERO_ANGLE else math.inf)
    return TrapezoidProfile(1.0, u_speed, u_accel)
