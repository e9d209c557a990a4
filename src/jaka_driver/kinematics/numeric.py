"""Iterative IK on Pinocchio's exact model: Newton polish, damped least squares, restarts.

Every solver here drives the joint-6 frame to a goal pose ``goal`` (``pin.SE3``, joint-6 frame
in the base frame) and measures success at the TCP: ``tcp_offset`` is the joint-6 → TCP
translation (m, joint-6 frame; None = the TCP is the joint-6 origin). Units: m, rad. The
Pinocchio ``Data`` (scratch space) is passed in by the caller, one per thread.

Each solver returns ``(success, q rad, position error m, rotation error rad, steps)``.
"""
from __future__ import annotations

import math
from typing import Sequence

import eigenpy
import numpy as np
import pinocchio as pin

#: Seed of the random restarts of :meth:`NumericIk.dls_restarts`: results are deterministic.
RESTART_RNG_SEED = 20240611
#: rad²: a Newton step longer than this is followed by one more even when the pose is within
#: tolerance, so the joints are exact too (the next step, and the joints' error, is of the
#: order of this step squared), not only the pose. Also in jaka_ik.c.
SETTLED_STEP2 = 1e-9
#: rad: how far :meth:`NumericIk.finish` lets damped least squares stray from a candidate and
#: still call the result that candidate's branch; its damped steps from the candidate or seed.
BRANCH_RADIUS = 0.3
FINISH_DLS_STEPS = 30


def tcp_error(E: pin.SE3, tcp_offset) -> tuple[float, float]:
    """(position m, rotation rad) error at the TCP, from E = current⁻¹·goal of joint 6.

    Plain-float arithmetic: for one 3x3 matrix it is several times cheaper than numpy calls.
    """
    (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz), _ = E.homogeneous.tolist()
    if tcp_offset is not None:
        # TCP displacement = p + (R - I)·offset, offset = joint 6 → TCP.
        ox, oy, oz = tcp_offset
        px += (r00 - 1.0) * ox + r01 * oy + r02 * oz
        py += r10 * ox + (r11 - 1.0) * oy + r12 * oz
        pz += r20 * ox + r21 * oy + (r22 - 1.0) * oz
    s = 0.5 * math.sqrt((r21 - r12) ** 2 + (r02 - r20) ** 2 + (r10 - r01) ** 2)
    rot = math.atan2(s, 0.5 * (r00 + r11 + r22 - 1.0))  # accurate at 0 and near π
    return math.sqrt(px * px + py * py + pz * pz), rot


class NumericIk:
    """The iterative solvers of one Pinocchio ``model`` whose joint ``joint6`` carries the
    flange. ``lower``/``upper``: joint limits, rad; ``weight2``: (1 / max_velocity)², (s/rad)²,
    the weight of the distance between configurations when restarts compete."""

    def __init__(self, model: pin.Model, joint6: int, lower: np.ndarray, upper: np.ndarray,
                 weight2: np.ndarray):
        self._pin = model
        self._joint6 = joint6
        self._lower, self._upper = lower, upper
        self._lower_list: Sequence[float] = lower.tolist()
        self._upper_list: Sequence[float] = upper.tolist()
        self._weight2 = weight2

    def pose_error(self, d: pin.Data, q: np.ndarray, goal: pin.SE3, tcp_offset
                   ) -> tuple[float, float]:
        """(position m, rotation rad) error at the TCP of joint positions ``q`` (rad)."""
        pin.forwardKinematics(self._pin, d, q)
        return tcp_error(d.oMi[self._joint6].actInv(goal), tcp_offset)

    def _within_limits(self, q: np.ndarray) -> bool:
        return all(lo <= x <= hi for lo, x, hi in zip(self._lower_list, q.tolist(),
                                                       self._upper_list))

    def polish(self, d: pin.Data, q0, goal: pin.SE3, tcp_offset, pos_tol: float,
               rot_tol: float, max_steps: int):
        """Newton steps on log6 of the joint-6 error, from a closed-form solution ``q0`` (rad).

        At least one step is taken: the closed form of the ideal chain is never within
        tolerance (``pos_tol`` m, ``rot_tol`` rad) of the real URDF, so checking before the
        first step would only cost time; and steps go on while they are longer than
        :data:`SETTLED_STEP2`. A step over 0.2 rad means a singular spot; the caller then tries
        something else.
        """
        m, j6 = self._pin, self._joint6
        q = np.array(q0, dtype=float)
        for it in range(1, max_steps + 1):
            pin.computeJointJacobians(m, d, q)
            E = d.oMi[j6].actInv(goal)
            # Eigen's LU through eigenpy: numpy's solve costs three times more per call.
            dq = eigenpy.PartialPivLU(pin.getJointJacobian(m, d, j6, pin.LOCAL)).solve(
                pin.log6(E).vector)
            step2 = float(dq @ dq)
            if not step2 < 0.04:  # also catches NaN
                return False, q, *tcp_error(E, tcp_offset), it
            q = q + dq
            pin.forwardKinematics(m, d, q)
            pe, re = tcp_error(d.oMi[j6].actInv(goal), tcp_offset)
            if pe <= pos_tol and re <= rot_tol and (step2 <= SETTLED_STEP2 or it == max_steps):
                if not self._within_limits(q):  # a joint on its limit stepped just past it
                    q = np.clip(q, self._lower, self._upper)
                    pe, re = self.pose_error(d, q, goal, tcp_offset)
                    return pe <= pos_tol and re <= rot_tol, q, pe, re, it
                return True, q, pe, re, it
        return False, q, pe, re, max_steps

    def finish(self, d: pin.Data, candidate, ref, goal: pin.SE3, tcp_offset, pos_tol: float,
               rot_tol: float, max_steps: int = 4):
        """The exact solution on the branch of ``candidate`` (rad, from a solver of the ideal
        chain): Newton :meth:`polish`; where that fails (next to a singularity the ideal
        chain's error turns into a long step), damped least squares from ``ref`` (rad, the
        seed: it knows its own branch) and then from the candidate, kept only if it ends within
        :data:`BRANCH_RADIUS` of the candidate."""
        ok, q, pe, re, steps = self.polish(d, candidate, goal, tcp_offset, pos_tol, rot_tol,
                                           max_steps)
        if ok:
            return ok, q, pe, re, steps
        best = (pe, re)
        cand = np.asarray(candidate, float)
        for start in (ref, cand):
            ok, q, pe, re, n = self.dls(d, start, goal, tcp_offset, pos_tol, rot_tol,
                                        FINISH_DLS_STEPS)
            steps += n
            if ok and float(np.max(np.abs(q - cand))) <= BRANCH_RADIUS:
                return self.settled(d, q, pe, re, goal, tcp_offset, pos_tol, rot_tol) + (steps,)
            best = min(best, (pe, re))
        return False, cand, best[0], best[1], steps

    def settled(self, d: pin.Data, q: np.ndarray, pe: float, re: float, goal: pin.SE3,
                tcp_offset, pos_tol: float, rot_tol: float):
        """``(True, q, position error, rotation error)`` for a ``q`` (rad) within tolerance
        (its errors ``pe`` m, ``re`` rad), after Newton steps that settle the joints too:
        damped least squares stops as soon as the pose is within tolerance."""
        ok, q2, pe2, re2, _ = self.polish(d, q, goal, tcp_offset, pos_tol, rot_tol, 2)
        return (True, q2, pe2, re2) if ok else (True, q, pe, re)

    def dls(self, d: pin.Data, q0, goal: pin.SE3, tcp_offset, pos_tol: float, rot_tol: float,
            max_iter: int):
        """Damped least squares on log6 of the joint-6 error from ``q0`` (rad), clamped to the
        joint limits.

        Levenberg-Marquardt damping ~ |e|²: heavy far away, vanishing at the solution, so it
        still converges quickly next to a singularity.
        """
        m, j6 = self._pin, self._joint6
        lo, hi = self._lower, self._upper
        q = np.clip(np.array(q0, dtype=float), lo, hi)
        for it in range(max_iter + 1):
            pin.computeJointJacobians(m, d, q)
            E = d.oMi[j6].actInv(goal)
            pe, re = tcp_error(E, tcp_offset)
            if pe <= pos_tol and re <= rot_tol:
                return True, q, pe, re, it
            if it == max_iter:
                break
            e = pin.log6(E).vector
            J = pin.getJointJacobian(m, d, j6, pin.LOCAL)
            dq = J.T @ np.linalg.solve(J @ J.T + (float(e @ e) + 1e-12) * np.eye(6), e)
            n = math.sqrt(float(dq @ dq))
            if n > 0.5:
                dq *= 0.5 / n
            q = np.clip(q + dq, lo, hi)
        return False, q, pe, re, it

    def dls_restarts(self, d: pin.Data, ref: np.ndarray, goal: pin.SE3, tcp_offset,
                     pos_tol: float, rot_tol: float, max_iter: int, restarts: int):
        """Damped least squares from ``ref`` (rad), then from ``restarts`` random
        configurations inside the limits (fixed RNG seed); of the successful runs the one
        nearest ``ref`` wins. On failure q is None and the errors are the best attempt's."""
        rng = np.random.default_rng(RESTART_RNG_SEED)
        best_fail = (math.inf, math.inf)
        found = []
        iters = 0
        starts = [ref] + [rng.uniform(self._lower, self._upper) for _ in range(restarts)]
        for k, q0 in enumerate(starts):
            ok, q, pe, re, n = self.dls(d, q0, goal, tcp_offset, pos_tol, rot_tol, max_iter)
            iters += n
            if ok:
                if k == 0:
                    return True, q, pe, re, iters  # the reference's own basin
                found.append((float(np.square(q - ref) @ self._weight2), q, pe, re))
            else:
                best_fail = min(best_fail, (pe, re))
        if found:
            _, q, pe, re = min(found, key=lambda f: f[0])
            return True, q, pe, re, iters
        return False, None, best_fail[0], best_fail[1], iters
