"""Overload of the twin's drives: what the arm can hold, and what happens when it cannot.

A joint drive has a torque limit (``max_effort``, N·m). A payload too heavy or too far out, or
an obstacle pushing while collision detection is off, asks for more: the joint falls behind
its setpoint and the arm sags. A real controller watches this following error, stops
protectively and closes the brakes; the twin does the same (:class:`FollowingErrorMonitor`),
so that nothing leaves the arm moving without a command.

:func:`holding_torque` answers the question before it happens: the joint torques (N·m) that
hold the arm still at its current pose with a given payload, so ``set_payload`` and
``clear_err`` can refuse what the drives could not hold.

Units: rad, N·m, kg, m (centroid in the flange frame = the ``link_6`` body frame).
"""
from __future__ import annotations

from typing import Callable, Sequence

import mujoco
import numpy as np

from .servo import JointServo
from .twin_model import FLANGE_BODY, Payload

# rad a joint may lag its setpoint before the drive counts as overloaded. Tracking at full
# speed stays under 1e-3 rad (servo gains of config/<model>.yaml); 0.05 rad is far beyond
# that and still only ~25 mm at the end of a 0.5 m lever.
FOLLOWING_ERROR_LIMIT = 0.05
# Share of a joint's torque limit that holding the arm still may use: the rest is left for
# accelerating it.
HOLDING_SHARE = 0.9


class FollowingErrorMonitor:
    """Calls ``on_overload(message)`` once when a joint lags its setpoint by more than
    :data:`FOLLOWING_ERROR_LIMIT`; re-armed by :meth:`rearm` (``clear_err``). Checked once per
    8 ms cycle in the physics thread, at the cycle's end, where the arm should be at the
    setpoint of the cycle."""

    def __init__(self, servo: JointServo, joint_names: Sequence[str],
                 on_overload: Callable[[str], None]):
        self._servo = servo
        self._names = list(joint_names)
        self._on_overload = on_overload
        self.armed = True

    def rearm(self) -> None:
        self.armed = True

    def check(self, d: mujoco.MjData) -> None:
        if not self.armed or self._servo.released:
            return
        k, lag = self._servo.following_error(d)
        if lag > FOLLOWING_ERROR_LIMIT:
            self.armed = False
            self._on_overload(f"protective stop: {self._names[k]} is {lag:.3f} rad behind its "
                              f"setpoint (limit {FOLLOWING_ERROR_LIMIT:g} rad): the drive cannot "
                              "hold the arm (payload too heavy or too far out, or pushed); brakes "
                              "closed")


def holding_torque(m: mujoco.MjModel, q: np.ndarray, payload: Payload, mass: float,
                   centroid: np.ndarray) -> np.ndarray:
    """Joint torques (N·m) holding the arm at rest at ``q`` (rad) with ``mass`` kg at
    ``centroid`` (m, flange frame) instead of the payload folded into ``m`` now.

    Gravity is linear in the masses: the torque of the arm with its current payload, minus
    that payload's own share, plus the new one's — each a point mass seen through the
    translational Jacobian of its point. Uses scratch data; ``m`` is not changed (call under
    the physics lock: ``m`` must not change meanwhile)."""
    d = mujoco.MjData(m)
    d.qpos[:6] = q
    mujoco.mj_forward(m, d)                 # qvel = 0: qfrc_bias is gravity alone
    body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, FLANGE_BODY)
    return (d.qfrc_bias[:6] - _point_gravity(m, d, body, payload.mass, payload.centroid)
            + _point_gravity(m, d, body, mass, np.asarray(centroid, float)))


def worst_joint(torque: np.ndarray, max_effort: np.ndarray) -> tuple[int, float]:
    """(index, share of its limit) of the joint closest to its torque limit."""
    share = np.abs(torque) / max_effort
    k = int(np.argmax(share))
    return k, float(share[k])


def _point_gravity(m: mujoco.MjModel, d: mujoco.MjData, body: int, mass: float,
                   local: np.ndarray) -> np.ndarray:
    """Torques (N·m) holding ``mass`` kg at ``local`` (m, ``body`` frame) against gravity."""
    if mass == 0.0:
        return np.zeros(6)
    point = d.xpos[body] + d.xmat[body].reshape(3, 3) @ local
    jacp = np.zeros((3, m.nv))
    mujoco.mj_jac(m, d, jacp, None, point, body)
    return jacp[:, :6].T @ (-mass * m.opt.gravity)
