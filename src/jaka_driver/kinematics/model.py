"""What the robot is: a JAKA arm's Pinocchio model, its FK, Jacobian, frames and IK dispatch.

Frames and units: everything is SI (m, rad) and every pose is a 4x4 homogeneous matrix.

* base frame = the URDF root ``base_link`` (the robot's mounting face);
* flange frame = the URDF link ``flange`` (= ``link_6``, JAKA's flange / "end" frame);
* ``tool`` = pose of the TCP in the flange frame (JAKA "tool frame"), identity by default;
* ``user`` = pose of the user frame in the base frame (JAKA "user frame"), identity by default.

Thread safety: one :class:`Kinematics` may be shared by any number of threads. The Pinocchio
``Model`` is read-only; each thread gets its own ``Data`` (scratch space) on first use.

IK strategy, the ideal chain's solutions first, numeric fallback: each of the three kinematic
structures of the JAKA arms has a solver listing the solutions of its ideal chain — the Zu
structure's closed form (:mod:`.closed_form`, 19 models), the spherical wrist's
(:mod:`.spherical_wrist`, MiniCobo) and the forearm roll's search (:mod:`.forearm_roll`, A12).
The branch nearest the seed is finished by Newton steps on Pinocchio's exact model
(:mod:`.numeric`); if that fails (a singular spot), damped least squares with restarts takes
over. The Zu closed form + Newton also exists compiled (:mod:`.native`): ``ik`` enters it once
per request when the library is built, and it computes the same solution as the Python path.
"""
from __future__ import annotations

import math
import threading
from typing import Callable, NamedTuple

import numpy as np
import pinocchio as pin

from ..common.models import RobotModel
from . import native
from .branches import Branches
from .chain import z_axis_placements
from .closed_form import ClosedForm, zu_geometry
from .forearm_roll import ForearmRoll
from .numeric import FINISH_DLS_STEPS, NumericIk
from .spherical_wrist import SLACK, SphericalWrist

_I4 = np.eye(4)
_I4.setflags(write=False)
# A seeded request on a structure without a compiled closed form (MiniCobo, A12) is first
# solved from the seed itself — damped least squares, at most SEED_STEPS steps — and the answer
# kept when no joint moved more than SEED_RADIUS (rad) from the seed: the seed's own branch, at a
# fraction of the cost of listing every branch. Also in jaka_ik.c (jk_local_seeded).
SEED_STEPS = 15
SEED_RADIUS = 0.5


class IkResult(NamedTuple):
    """Outcome of an IK request.

    ``q`` (rad, J1..J6) is ``None`` unless ``success``. ``position_error`` (m) and
    ``rotation_error`` (rad) are those of the returned ``q`` (or of the best attempt on failure),
    measured at the TCP. ``iterations`` counts Newton/DLS steps over all attempts. (A named
    tuple, not a dataclass: built on every IK call, it costs a third of the time.)
    """

    success: bool
    q: np.ndarray | None
    position_error: float
    rotation_error: float
    iterations: int
    message: str


def _finite(a: np.ndarray) -> bool:
    """No NaN/inf in ``a``; values beyond 1e150 count as infinite, as the compiled path
    (jaka_ik.c ``sane``) counts them. NaN fails the comparison. (It was ``v @ v`` finite: a
    value of 1e200, refused on purpose, overflowed the square and numpy warned "overflow
    encountered in matmul" on every such refusal.) A plain loop, not numpy's ``max``: every
    sample's TCP passes here on a thread that has just woken, where a numpy reduction over a
    few numbers costs 20-40 µs (jaka_driver.common.joint_limits says how it was measured)."""
    return all(abs(v) <= 1e150 for v in np.asarray(a).ravel().tolist())


def _as_pose(T, name: str) -> np.ndarray:
    """``T`` as a finite 4x4 float array (identity for None); ValueError naming ``name``."""
    if T is None:
        return _I4
    a = np.asarray(T, dtype=float)
    if a.shape != (4, 4) or not _finite(a):
        raise ValueError(f"{name} must be a finite 4x4 homogeneous matrix, got shape {a.shape}")
    return a


def _inv(T: np.ndarray) -> np.ndarray:
    """Inverse of a rigid 4x4 transform."""
    out = np.eye(4)
    R = T[:3, :3].T
    out[:3, :3] = R
    out[:3, 3] = -R @ T[:3, 3]
    return out


class Kinematics:
    """FK, Jacobian and IK of one :class:`RobotModel` (see the module docstring for frames)."""

    def __init__(self, model: RobotModel):
        self.model = model
        self._pin = pin.buildModelFromXML(model.urdf_xml)
        names = tuple(self._pin.names[1:])
        if names != tuple(model.joint_names) or self._pin.nq != 6:
            raise ValueError(f"{model.urdf_path}: Pinocchio sees joints {names}, "
                             f"expected {model.joint_names}")
        self._flange_id = self._pin.getFrameId("flange")
        frame = self._pin.frames[self._flange_id]
        self._joint6 = frame.parentJoint
        # Flange pose in the joint-6 frame; identity in our URDFs, kept general.
        self._F = frame.placement.homogeneous
        self._F_is_identity = bool(np.allclose(self._F, _I4, atol=0.0))
        self._lower = np.asarray(model.lower, dtype=float)
        self._upper = np.asarray(model.upper, dtype=float)
        self._middle = 0.5 * (self._lower + self._upper)
        # Distance between configurations is measured in seconds of joint travel: a big joint
        # that moves slowly weighs more than a fast wrist.
        self._weight = 1.0 / np.asarray(model.max_velocity, dtype=float)
        self._weight2 = self._weight ** 2
        self._local = threading.local()
        #: (the user frame's shape, dtype and bytes, its inverse): the last one asked for
        self._user_inverse: tuple | None = None
        # Plain-float copies for the hot path of the seed's clamping.
        self._lower_list = self._lower.tolist()
        self._upper_list = self._upper.tolist()
        self._middle_list = self._middle.tolist()
        self._numeric = NumericIk(self._pin, self._joint6, self._lower, self._upper,
                                  self._weight2)
        # The solver of the model's structure (None: numeric IK only). The compiled library
        # (None when it is not built) has the Zu closed form, and for the other structures
        # the damped least squares from the seed they start with (SEED_STEPS).
        self._solver = None
        geometry = zu_geometry(model.chain)
        if geometry is not None:
            self._solver = ClosedForm(geometry, self._lower, self._upper, self._weight2,
                                      model.joint_names)
        else:
            branches = Branches(self._lower, self._upper, self._weight2, model.joint_names,
                                SLACK)
            self._solver = (SphericalWrist.fit(model.chain, branches)
                            or ForearmRoll.fit(model.chain, branches))
        self._local_first = geometry is None
        placements, fix6 = z_axis_placements(model.chain)
        self._native: native.NativeIk | None = native.load(
            placements, fix6, geometry, self._lower, self._upper, self._weight2)

    # ------------------------------------------------------------------ helpers
    def _data(self) -> pin.Data:
        d = getattr(self._local, "data", None)
        if d is None:
            d = self._local.data = self._pin.createData()
        return d

    def _check_q(self, q) -> np.ndarray:
        """``q`` as 6 finite joint positions (rad); ValueError otherwise."""
        a = np.asarray(q, dtype=float)
        if a.shape != (6,) or not _finite(a):
            raise ValueError(f"joint positions must be 6 finite values in rad, got {np.shape(q)}")
        return a

    def _seed_ref(self, seed) -> list[float]:
        """The seed (rad) checked and clamped into the joint limits, as plain floats."""
        return [min(h, max(lo, x)) for x, lo, h in
                zip(self._check_q(seed).tolist(), self._lower_list, self._upper_list)]

    # ------------------------------------------------------------------ forward kinematics
    def flange_pose(self, q) -> np.ndarray:
        """Flange pose (4x4, m) in the base frame for joint positions ``q`` (rad)."""
        d = self._data()
        pin.forwardKinematics(self._pin, d, self._check_q(q))
        return pin.updateFramePlacement(self._pin, d, self._flange_id).homogeneous

    def tcp_pose(self, q, tool=None, user=None) -> np.ndarray:
        """TCP pose (4x4, m) in the user frame for joint positions ``q`` (rad):
        ``user⁻¹ · flange(q) · tool``, with ``tool`` the TCP pose in the flange frame and
        ``user`` the user frame's pose in the base frame (4x4, m; None = identity)."""
        T = self.flange_pose(q)
        if tool is not None:
            T = T @ _as_pose(tool, "tool")
        if user is not None:
            T = self._inverse_of_user(user) @ T
        return T

    def _inverse_of_user(self, user) -> np.ndarray:
        """``user⁻¹`` (4x4, m), checked; the last user frame's is kept: every sample's TCP
        needs it and a user frame changes rarely (an inverse and its checks were a fifth of
        the state publisher's work per sample)."""
        key = (user.shape, user.dtype.str, user.tobytes()) if isinstance(user, np.ndarray) \
            else None
        kept = self._user_inverse
        if key is not None and kept is not None and kept[0] == key:
            return kept[1]
        inverse = _inv(_as_pose(user, "user"))
        if key is not None:
            self._user_inverse = (key, inverse)
        return inverse

    def jacobian(self, q, tool=None) -> np.ndarray:
        """6x6 Jacobian of the TCP at joint positions ``q`` (rad): rows (vx, vy, vz, ωx, ωy, ωz)
        in base-frame axes; ``tool`` is the TCP pose in the flange frame (4x4, m; None = the
        flange).

        Linear rows are the velocity (m/s per rad/s) of the TCP point, angular rows the angular
        velocity — Pinocchio's LOCAL_WORLD_ALIGNED convention.
        """
        m, d, f = self._pin, self._data(), self._flange_id
        pin.computeJointJacobians(m, d, self._check_q(q))  # also the joint placements
        R = pin.updateFramePlacement(m, d, f).rotation
        J = pin.getFrameJacobian(m, d, f, pin.LOCAL_WORLD_ALIGNED)
        if tool is not None:
            # v_tcp = v_flange + ω × r, r = flange→TCP in base axes.
            r = R @ _as_pose(tool, "tool")[:3, 3]
            w = J[3:]
            J = J.copy()
            J[:3] += np.cross(w.T, r).T
        return J

    def tcp_linear_speed(self, q, qd, tool=None) -> float:
        """The speed (m/s) of the TCP at the joints ``q`` (rad) moving at ``qd`` (rad/s):
        ``|J_linear · qd|`` of :meth:`jacobian`, from Pinocchio's frame velocity in one pass
        (the flange's velocity + ω × the flange → TCP offset). ``tool`` as in :meth:`tcp_pose`."""
        m, d, f = self._pin, self._data(), self._flange_id
        pin.forwardKinematics(m, d, self._check_q(q), np.asarray(qd, dtype=float))
        flange = pin.updateFramePlacement(m, d, f)
        twist = pin.getFrameVelocity(m, d, f, pin.LOCAL_WORLD_ALIGNED)
        vx, vy, vz = twist.linear.tolist()
        if tool is not None:
            rx, ry, rz = (flange.rotation @ _as_pose(tool, "tool")[:3, 3]).tolist()
            wx, wy, wz = twist.angular.tolist()
            vx, vy, vz = vx + wy * rz - wz * ry, vy + wz * rx - wx * rz, vz + wx * ry - wy * rx
        return math.sqrt(vx * vx + vy * vy + vz * vz)

    def tcp_pose_and_sigma(self, q, tool=None) -> tuple[np.ndarray, float]:
        """(:meth:`tcp_pose` with ``tool``, the smallest singular value of :meth:`jacobian`
        with ``tool``) at the joints ``q`` (rad): what a velocity jog looks at each cycle, in
        one pass over the chain — one C call when the compiled library is built (the same
        numbers to rounding), else one Pinocchio pass and an SVD. ``tool`` as in
        :meth:`tcp_pose` (4x4, m; None = the flange)."""
        return self.tcp_measure(tool)(q)

    def tcp_measure(self, tool=None) -> Callable[[np.ndarray], tuple[np.ndarray, float]]:
        """:meth:`tcp_pose_and_sigma` for one ``tool``, taken (checked, laid out for C) once."""
        X = None if tool is None else np.ascontiguousarray(_as_pose(tool, "tool"), dtype=float)
        compiled = self._native if self._F_is_identity else None

        def measure(q) -> tuple[np.ndarray, float]:
            if compiled is not None:
                got = compiled.tcp_sigma(q, X)
                if got is not None:
                    return got
            m, d, f = self._pin, self._data(), self._flange_id
            pin.computeJointJacobians(m, d, self._check_q(q))   # also the joint placements
            flange = pin.updateFramePlacement(m, d, f)
            J = pin.getFrameJacobian(m, d, f, pin.LOCAL_WORLD_ALIGNED)
            T = flange.homogeneous
            if X is not None:
                J = J.copy()
                J[:3] += np.cross(J[3:].T, flange.rotation @ X[:3, 3]).T
                T = T @ X
            return T, float(np.linalg.svd(J, compute_uv=False)[-1])
        return measure

    # ------------------------------------------------------------------ inverse kinematics
    def ik(self, target, seed=None, tool=None, user=None, *, pos_tol: float = 1e-6,
           rot_tol: float = 1e-6, max_iter: int = 100, restarts: int = 8) -> IkResult:
        """Joint positions (rad) that put the TCP at ``target`` (4x4, m: pose of the TCP in the
        user frame). ``tool``: TCP pose in the flange frame, ``user``: the user frame's pose in
        the base frame (4x4, m; None = identity, the flange in the base frame).

        With a ``seed`` (rad) the solution of the seed's configuration (the one nearest to it,
        each joint taken at the 2π-turn nearest to the seed) is returned, so a path solved point
        by point never flips elbow, shoulder or wrist. Without a seed the solution nearest to
        the middle of the joint limits is returned. Results are deterministic.

        ``pos_tol`` (m) and ``rot_tol`` (rad) bound the TCP error of a successful result.
        ``max_iter`` and ``restarts`` bound the damped-least-squares fallback (restarts use a
        fixed random seed).
        """
        compiled = self._native
        if compiled is not None and seed is not None and tool is None and user is None \
                and self._F_is_identity:
            # The commonest request goes to C as it is. This is its one entry into C whatever
            # the outcome: a second call would compute the same refusal again.
            fast = (compiled.solve_local_seeded(target, seed, pos_tol, rot_tol, SEED_STEPS,
                                                SEED_RADIUS) if self._local_first else
                    compiled.solve_seeded(target, seed, pos_tol, rot_tol))
            if fast is not None:
                return IkResult(True, *fast, "ok")
            compiled = None     # refused there, or malformed input the checks below refuse
            local_tried = True
        else:
            local_tried = False
        target = _as_pose(target, "target")
        ref = self._middle_list if seed is None else self._seed_ref(seed)
        goal_T, tcp_offset = self._joint6_goal(target, tool, user)
        if compiled is not None and not self._local_first:
            fast = compiled.solve(goal_T, ref, tcp_offset, pos_tol, rot_tol)
            if fast is not None:
                return IkResult(True, *fast, "ok")
        return self._ik_python(goal_T, ref, tcp_offset, pos_tol, rot_tol, max_iter, restarts,
                               seed is not None, local_tried)

    def seeded_ik(self, tool=None) -> Callable[[np.ndarray, np.ndarray], np.ndarray | None]:
        """``solve(target, seed)``: ``ik(target, seed=seed, tool=tool).q``, or None where that
        fails, for one ``tool`` (4x4, m; None = the flange) taken once — its inverse is not
        recomputed on every request, as a velocity jog asks one every 8 ms cycle. The same
        steps as :meth:`ik`, so the same solution."""
        if tool is None or not self._F_is_identity:
            def solve_any(target, seed):
                result = self.ik(target, seed=seed, tool=tool)
                return result.q if result.success else None
            return solve_any
        X = _as_pose(tool, "tool").copy()
        X_inv = _inv(X)
        offset = None if not X[:3, 3].any() else tuple(X[:3, 3].tolist())
        if np.array_equal(X, _I4) and self._native is not None and not self._local_first:
            def solve_at_flange(target, seed):
                # target @ I⁻¹ is target, and the library's flange entry clamps the seed as
                # _seed_ref does: ik's compiled solve in one call
                fast = self._native.solve_seeded(target, seed, 1e-6, 1e-6)
                if fast is not None:
                    return fast[0]
                goal_T = _as_pose(target, "target") @ X_inv
                result = self._ik_python(goal_T, self._seed_ref(seed), offset, 1e-6, 1e-6, 100,
                                         8, True)
                return result.q if result.success else None
            return solve_at_flange

        def solve(target, seed):
            goal_T = _as_pose(target, "target") @ X_inv
            ref = self._seed_ref(seed)
            compiled = self._native
            if compiled is not None and not self._local_first:
                fast = compiled.solve(goal_T, ref, offset, 1e-6, 1e-6)
                if fast is not None:
                    return fast[0]
            result = self._ik_python(goal_T, ref, offset, 1e-6, 1e-6, 100, 8, True)
            return result.q if result.success else None
        return solve

    def _ik_python(self, goal_T: np.ndarray, ref: list[float], tcp_offset, pos_tol: float,
                   rot_tol: float, max_iter: int, restarts: int, seeded: bool,
                   local_tried: bool = False) -> IkResult:
        """The IK in Python for the joint-6 goal ``goal_T`` (4x4, m, base frame) near ``ref``
        (rad): for the structures that start there, damped least squares from the seed
        (SEED_STEPS; unless the compiled path has just tried that: ``local_tried``); then the ideal
        chain's nearest branch finished on the exact chain, its next two branches, and damped
        least squares with restarts. Also explains every failure."""
        d, numeric, solver = self._data(), self._numeric, self._solver
        goal = pin.SE3(goal_T)
        iters = 0
        if seeded and self._local_first and not local_tried:
            ok, q, pe, re, iters = numeric.dls(d, ref, goal, tcp_offset, pos_tol, rot_tol,
                                               SEED_STEPS)
            if ok:
                _, q, pe, re = numeric.settled(d, q, pe, re, goal, tcp_offset, pos_tol, rot_tol)
                if float(np.max(np.abs(q - np.asarray(ref)))) <= SEED_RADIUS:
                    return IkResult(True, q, pe, re, iters, "ok")
        cands, why = ([], "") if solver is None else \
            solver.solutions(goal_T, ref, nearest_only=True)
        best = (math.inf, math.inf)
        ref = np.array(ref)
        if cands:
            ok, q, pe, re, iters = numeric.finish(d, cands[0][1], ref, goal, tcp_offset,
                                                  pos_tol, rot_tol)
            if ok:
                return IkResult(True, q, pe, re, iters, "ok")
            best = (pe, re)
            # Rare (a singular spot): try the next branches before the iterative fallback.
            for _, c in solver.solutions(goal_T, ref)[0][1:3]:
                ok, q, pe, re, n = numeric.finish(d, c, ref, goal, tcp_offset, pos_tol,
                                                  rot_tol)
                iters += n
                if ok:
                    return IkResult(True, q, pe, re, iters, "ok")
                best = min(best, (pe, re))
        if why:
            # The ideal chain's solver covers every solution; when it finds none, neither
            # would DLS with restarts. Only next to a singularity can the ideal chain's sub-mm
            # error hide a solution the seed is already near: look there once.
            if seeded:
                ok, q, pe, re, n = numeric.dls(d, ref, goal, tcp_offset, pos_tol, rot_tol,
                                               FINISH_DLS_STEPS)
                iters += n
                if ok:
                    _, q, pe, re = numeric.settled(d, q, pe, re, goal, tcp_offset, pos_tol,
                                                   rot_tol)
                    return IkResult(True, q, pe, re, iters, "ok (damped least squares)")
            return IkResult(False, None, *numeric.pose_error(d, ref, goal, tcp_offset), iters,
                            why)
        ok, q, pe, re, n = numeric.dls_restarts(d, ref, goal, tcp_offset, pos_tol, rot_tol,
                                                max_iter, restarts)
        iters += n
        if ok:
            return IkResult(True, q, pe, re, iters, "ok (damped least squares)")
        pe, re = min(best, (pe, re))
        return IkResult(False, None, pe, re, iters,
                        f"no IK solution within tolerance: best TCP error {pe * 1e3:.3g} mm, "
                        f"{math.degrees(re):.3g} deg")

    def ik_all(self, target, tool=None, user=None, *, reference=None, pos_tol: float = 1e-6,
               rot_tol: float = 1e-6) -> list[np.ndarray]:
        """All distinct IK solutions (rad, up to 8) inside the joint limits, nearest first, for
        ``target`` (4x4, m: the TCP in the user frame; ``tool`` and ``user`` as in :meth:`ik`).
        ``pos_tol`` (m) and ``rot_tol`` (rad) bound the TCP error of each listed solution.

        Each joint is taken at the 2π-turn nearest to ``reference`` (rad; default the middle of
        the limits); the other turn of a ±2π joint is not listed separately.
        """
        target = _as_pose(target, "target")
        ref = self._middle_list if reference is None else self._check_q(reference).tolist()
        goal_T, tcp_offset = self._joint6_goal(target, tool, user)
        out: list[np.ndarray] = []
        if self._solver is None:
            return out
        goal, d = pin.SE3(goal_T), self._data()
        for _, c in self._solver.solutions(goal_T, ref)[0]:
            ok, q, *_ = self._numeric.finish(d, c, np.asarray(c), goal, tcp_offset, pos_tol,
                                             rot_tol, 6)
            if ok and all(np.max(np.abs(q - o)) > 1e-6 for o in out):
                out.append(q)
        return out

    # ------------------------------------------------------------------ IK internals
    def _joint6_goal(self, target, tool, user) -> tuple[np.ndarray, np.ndarray | None]:
        """Goal pose (4x4, m) of the joint-6 frame in the base frame, and the TCP offset (m, in
        the joint-6 frame; None when the TCP is the joint-6 origin)."""
        T = target
        if user is not None:
            T = _as_pose(user, "user") @ T
        X = None  # joint-6 frame → TCP
        if tool is not None:
            X = _as_pose(tool, "tool")
        if not self._F_is_identity:
            X = self._F if X is None else self._F @ X
        if X is not None:
            T = T @ _inv(X)
        offset = None if X is None or not X[:3, 3].any() else tuple(X[:3, 3].tolist())
        return T, offset
