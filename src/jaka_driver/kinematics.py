"""Forward and inverse kinematics of a JAKA Zu arm on Pinocchio, with a closed-form IK.

Frames and units: everything is SI (m, rad) and every pose is a 4x4 homogeneous matrix.

* base frame = the URDF root ``base_link`` (the robot's mounting face);
* flange frame = the URDF link ``flange`` (= ``link_6``, JAKA's flange / "end" frame);
* ``tool`` = pose of the TCP in the flange frame (JAKA "tool frame"), identity by default;
* ``user`` = pose of the user frame in the base frame (JAKA "user frame"), identity by default.

Thread safety: one :class:`Kinematics` may be shared by any number of threads. The Pinocchio
``Model`` is read-only; each thread gets its own ``Data`` (scratch space) on first use.

IK strategy: the Zu arms are UR-type (three parallel axes J2–J4, wrist axes J5 ⟂ J4, J6 ⟂ J5),
so the up-to-8 solutions of the ideal geometry have a closed form (:meth:`Kinematics._solutions`).
The official URDFs are not exactly ideal (rpy written as 1.5708, a 1.2e-5 m offset in joint_4's
origin), so the chosen branch is finished by one or two Newton steps on Pinocchio's exact model.
If that fails (a non-UR model, or a singular spot), a damped-least-squares solver takes over.
The seeded fast path (closed form + Newton) also exists compiled (:mod:`.native_ik`), which
``ik`` tries first when the library is built; it computes the same solution.
"""
from __future__ import annotations

import math
import threading
from typing import NamedTuple

import eigenpy
import numpy as np
import pinocchio as pin

from . import native_ik
from .models import RobotModel

_TWO_PI = 2.0 * math.pi
_I4 = np.eye(4)
_I4.setflags(write=False)


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
    """No NaN/inf in ``a`` (values beyond 1e150 count as infinite): one dot product is several
    times cheaper than ``np.isfinite(a).all()``, and this runs on every FK/IK call."""
    v = a.reshape(-1)
    return math.isfinite(v @ v)


def _as_pose(T, name: str) -> np.ndarray:
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
        self._dh = self._ur_lengths()
        # Joint-1 frame origin in the base (base offset + d1); its rotation is identity.
        self._shoulder = tuple(self._pin.jointPlacements[1].translation.tolist())
        # Plain-float copies for the closed-form hot path.
        self._lower_list = self._lower.tolist()
        self._upper_list = self._upper.tolist()
        self._middle_list = self._middle.tolist()
        self._weight2_list = self._weight2.tolist()
        # The compiled fast path (None without the built library, or for a non-UR chain).
        self._native = None if self._dh is None else native_ik.load(
            [(p.rotation, p.translation) for p in list(self._pin.jointPlacements)[1:7]],
            self._dh, self._shoulder, self._lower, self._upper, self._weight2)

    # ------------------------------------------------------------------ helpers
    def _data(self) -> pin.Data:
        d = getattr(self._local, "data", None)
        if d is None:
            d = self._local.data = self._pin.createData()
        return d

    def _ur_lengths(self) -> tuple[float, float, float, float, float] | None:
        """(a2, a3, d4, d5, d6) in m if the chain has the UR-type layout the closed form assumes.

        Small deviations (up to 1e-3 m / rad) are accepted: the Newton polish removes them.
        """
        jp = [self._pin.jointPlacements[i] for i in range(1, 7)]
        rx = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float)  # Rx(+pi/2)
        want_R = [np.eye(3), rx, np.eye(3), np.eye(3), rx, rx.T]
        if any(not np.allclose(p.rotation, R, atol=1e-3) for p, R in zip(jp[1:], want_R[1:])):
            return None
        t = [p.translation for p in jp]
        a2, a3, d4, d5, d6 = t[2][0], t[3][0], -t[3][2], -t[4][1], t[5][1]
        off = [t[1], (0, t[2][1], t[2][2]), (0, t[3][1], 0), (t[4][0], 0, t[4][2]), (t[5][0], 0, t[5][2])]
        if np.max(np.abs(np.array(off, float))) > 1e-3 or not np.allclose(jp[0].rotation, np.eye(3)):
            return None
        return float(a2), float(a3), float(d4), float(d5), float(d6)

    def _check_q(self, q) -> np.ndarray:
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
        """TCP pose (4x4, m) in the user frame: ``user⁻¹ · flange(q) · tool``."""
        T = self.flange_pose(q)
        if tool is not None:
            T = T @ _as_pose(tool, "tool")
        if user is not None:
            T = _inv(_as_pose(user, "user")) @ T
        return T

    def jacobian(self, q, tool=None) -> np.ndarray:
        """6x6 Jacobian of the TCP: rows (vx, vy, vz, ωx, ωy, ωz) in base-frame axes.

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

    # ------------------------------------------------------------------ inverse kinematics
    def ik(self, target, seed=None, tool=None, user=None, *, pos_tol: float = 1e-6,
           rot_tol: float = 1e-6, max_iter: int = 100, restarts: int = 8) -> IkResult:
        """Joint positions that put the TCP at ``target`` (4x4, pose of the TCP in the user frame).

        With a ``seed`` (rad) the solution of the seed's configuration (the one nearest to it,
        each joint taken at the 2π-turn nearest to the seed) is returned, so a path solved point
        by point never flips elbow, shoulder or wrist. Without a seed the solution nearest to
        the middle of the joint limits is returned. Results are deterministic.

        ``pos_tol`` (m) and ``rot_tol`` (rad) bound the TCP error of a successful result.
        ``max_iter`` and ``restarts`` bound the damped-least-squares fallback (restarts use a
        fixed random seed).
        """
        native = self._native
        if native is not None and seed is not None and tool is None and user is None \
                and self._F_is_identity:
            fast = native.solve_seeded(target, seed, pos_tol, rot_tol)
            if fast is not None:
                return IkResult(True, *fast, "ok")
        target = _as_pose(target, "target")
        ref = self._middle_list if seed is None else self._seed_ref(seed)
        goal_T, tcp_offset = self._joint6_goal(target, tool, user)
        if native is not None:
            fast = native.solve(goal_T, ref, tcp_offset, pos_tol, rot_tol)
            if fast is not None:
                return IkResult(True, *fast, "ok")
        goal = pin.SE3(goal_T)
        cands, why = self._solutions(goal_T, ref, nearest_only=True)
        iters = 0
        best = (math.inf, math.inf)
        if cands:
            ok, q, pe, re, iters = self._polish(cands[0][1], goal, tcp_offset, pos_tol, rot_tol, 4)
            if ok:
                return IkResult(True, q, pe, re, iters, "ok")
            best = (pe, re)
            # Rare (a singular spot): try the next branches before the iterative fallback.
            for _, c in self._solutions(goal_T, ref)[0][1:3]:
                ok, q, pe, re, n = self._polish(c, goal, tcp_offset, pos_tol, rot_tol, 4)
                iters += n
                if ok:
                    return IkResult(True, q, pe, re, iters, "ok")
                best = min(best, (pe, re))
        ref = np.array(ref)
        if why and self._dh is not None:
            # The closed form covers every solution; when it finds none, neither would DLS.
            return IkResult(False, None, *self._pose_error_of(ref, goal, tcp_offset), iters, why)
        ok, q, pe, re, n = self._dls_restarts(ref, goal, tcp_offset, pos_tol, rot_tol, max_iter,
                                              restarts)
        iters += n
        if ok:
            return IkResult(True, q, pe, re, iters, "ok (damped least squares)")
        pe, re = min(best, (pe, re))
        return IkResult(False, None, pe, re, iters,
                        f"no IK solution within tolerance: best TCP error {pe * 1e3:.3g} mm, "
                        f"{math.degrees(re):.3g} deg")

    def ik_all(self, target, tool=None, user=None, *, reference=None, pos_tol: float = 1e-6,
               rot_tol: float = 1e-6) -> list[np.ndarray]:
        """All distinct IK solutions (up to 8) inside the joint limits, nearest first.

        Each joint is taken at the 2π-turn nearest to ``reference`` (rad; default the middle of
        the limits); the other turn of a ±2π joint is not listed separately.
        """
        target = _as_pose(target, "target")
        ref = self._middle_list if reference is None else self._check_q(reference).tolist()
        goal_T, tcp_offset = self._joint6_goal(target, tool, user)
        goal = pin.SE3(goal_T)
        out: list[np.ndarray] = []
        for _, c in self._solutions(goal_T, ref)[0]:
            ok, q, *_ = self._polish(c, goal, tcp_offset, pos_tol, rot_tol, 6)
            if ok and all(np.max(np.abs(q - o)) > 1e-6 for o in out):
                out.append(q)
        return out

    # ------------------------------------------------------------------ IK internals
    def _joint6_goal(self, target, tool, user) -> tuple[np.ndarray, np.ndarray | None]:
        """Goal pose (4x4) of the joint-6 frame in the base, and the TCP offset in that frame."""
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

    def _solutions(self, T: np.ndarray, ref: list[float], nearest_only: bool = False
                   ) -> tuple[list, str]:
        """Closed-form solutions for the joint-6 pose ``T`` (4x4 in the base frame).

        Returns ``([(distance, q), ...] nearest first, reason-if-none)``. Each joint is taken at
        the 2π-turn nearest to ``ref`` and moved a turn into its limits if needed; solutions
        outside the limits are dropped. Distance = Σ ((q - ref) / max_velocity)².
        ``nearest_only`` skips branches that cannot beat the nearest one found so far (the list
        then starts with the nearest solution but may miss others).

        Plain floats, not numpy: for 8 small solutions the interpreter is faster than numpy's
        per-call overhead, and this is the hot path of every seeded IK.

        Derivation for the ideal chain (origin on the shoulder, x1/y1 = joint-1 frame axes after
        turning by q1): the joint-5 centre p5 = p - d6·z6 lies d4 off the arm plane along y1,
        which fixes q1 (2 ways); z6·y1 = -cos q5 (2 ways); q6 follows from x6·y1 = -sin q5 cos q6
        and y6·y1 = sin q5 sin q6; y4 = sin q6·x6 + cos q6·y6 gives q2+q3+q4; the planar 2R elbow
        (a2, a3) reaching p4 = p5 + d5·y4 gives q3 (2 ways) and q2.
        """
        if self._dh is None:
            return [], ""
        a2, a3, d4, d5, d6 = self._dh
        (xx, yx, zx, px), (xy, yy, zy, py), (xz, yz, zz, pz) = T[:3].tolist()
        ox, oy, oz = self._shoulder
        p5x, p5y, p5z = px - ox - d6 * zx, py - oy - d6 * zy, pz - oz - d6 * zz
        r = math.hypot(p5x, p5y)
        # Slack for the URDF's departures from the ideal chain; the polish decides there.
        if r < d4 * (1.0 - 1e-4):
            return [], "target out of reach: wrist centre too close to the joint-1 axis"
        lo, hi, w2 = self._lower_list, self._upper_list, self._weight2_list
        r1, r2, r3, r4, r5, r6 = ref
        pi, two_pi = math.pi, _TWO_PI
        bad = [0] * 6

        def near(x: float, j: int, r: float) -> float | None:
            v = r + (x - r + pi) % two_pi - pi
            if v > hi[j]:
                v -= two_pi
            elif v < lo[j]:
                v += two_pi
            if lo[j] <= v <= hi[j]:
                return v
            bad[j] += 1
            return None

        phi = math.atan2(p5y, p5x)
        alpha = math.asin(min(d4 / r, 1.0))
        out = []
        best = math.inf  # with nearest_only, subtrees already farther than this are skipped
        reach = False
        shoulders = []
        for q1 in (phi - alpha, phi + alpha - pi):
            v1 = near(q1, 0, r1)
            if v1 is not None:
                shoulders.append((w2[0] * (v1 - r1) ** 2, q1, v1))
        shoulders.sort()
        for dist1, q1, v1 in shoulders:
            if dist1 >= best:
                break
            c1, s1 = math.cos(q1), math.sin(q1)
            c5 = min(1.0, max(-1.0, s1 * zx - c1 * zy))
            xy1, yy1 = c1 * xy - s1 * xx, c1 * yy - s1 * yx
            q5a = math.acos(c5)
            wrists = []
            for q5 in ((q5a, -q5a) if q5a > 1e-12 else (0.0,)):
                s5 = math.sin(q5)
                # At sin q5 = 0 the J6 axis is parallel to J2..J4 and only q4 ± q6 is defined:
                # keep the reference q6. The slack covers the URDF's departures from the ideal
                # chain, which leave sin q5 ~ 1e-5 at a truly singular pose.
                q6 = (math.atan2(yy1, -xy1) if s5 > 1e-4 else
                      math.atan2(-yy1, xy1) if s5 < -1e-4 else r6)
                v5, v6 = near(q5, 4, r5), near(q6, 5, r6)
                if v5 is not None and v6 is not None:
                    wrists.append((dist1 + w2[4] * (v5 - r5) ** 2 + w2[5] * (v6 - r6) ** 2,
                                   q6, v5, v6))
            wrists.sort()
            for dist56, q6, v5, v6 in wrists:
                if dist56 >= best:
                    break
                c6, s6 = math.cos(q6), math.sin(q6)
                y4x, y4y, y4z = s6 * xx + c6 * yx, s6 * xy + c6 * yy, s6 * xz + c6 * yz
                q234 = math.atan2(-(c1 * y4x + s1 * y4y), y4z)
                u = c1 * (p5x + d5 * y4x) + s1 * (p5y + d5 * y4y)
                v = p5z + d5 * y4z
                c3 = (u * u + v * v - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
                if abs(c3) > 1.0 + 1e-4:
                    continue
                reach = True
                q3a = math.acos(min(1.0, max(-1.0, c3)))
                for q3 in ((q3a, -q3a) if q3a > 1e-12 else (0.0,)):
                    q2 = math.atan2(v, u) - math.atan2(a3 * math.sin(q3), a2 + a3 * c3)
                    v2, v3, v4 = near(q2, 1, r2), near(q3, 2, r3), near(q234 - q2 - q3, 3, r4)
                    if v2 is None or v3 is None or v4 is None:
                        continue
                    dist = (dist56 + w2[1] * (v2 - r2) ** 2 + w2[2] * (v3 - r3) ** 2
                            + w2[3] * (v4 - r4) ** 2)
                    out.append((dist, (v1, v2, v3, v4, v5, v6)))
                    if nearest_only and dist < best:
                        best = dist
        if out:
            out.sort(key=lambda s: s[0])
            return out, ""
        if not reach and not any(bad[1:4]) and not bad[0]:
            return [], "target out of reach: beyond the elbow's range"
        names = ", ".join(n for n, b in zip(self.model.joint_names, bad) if b)
        return [], f"every IK solution violates joint limits ({names})"

    def _pose_error_of(self, q, goal: pin.SE3, tcp_offset) -> tuple[float, float]:
        d = self._data()
        pin.forwardKinematics(self._pin, d, q)
        return self._tcp_error(d.oMi[self._joint6].actInv(goal), tcp_offset)

    @staticmethod
    def _tcp_error(E: pin.SE3, tcp_offset) -> tuple[float, float]:
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

    def _within_limits(self, q: np.ndarray) -> bool:
        return all(lo <= x <= hi for lo, x, hi in zip(self._lower_list, q.tolist(),
                                                       self._upper_list))

    def _polish(self, q0, goal: pin.SE3, tcp_offset, pos_tol, rot_tol, max_steps: int):
        """Newton steps on log6 of the joint-6 error, from a closed-form solution.

        Returns (success, q, position error m, rotation error rad, steps). At least one step is
        taken: the closed form of the ideal chain is never within tolerance of the real URDF,
        so checking before the first step would only cost time. A step over 0.2 rad means a
        singular spot; the caller then tries something else.
        """
        m, d, j6 = self._pin, self._data(), self._joint6
        q = np.array(q0, dtype=float)
        for it in range(1, max_steps + 1):
            pin.computeJointJacobians(m, d, q)
            E = d.oMi[j6].actInv(goal)
            # Eigen's LU through eigenpy: numpy's solve costs three times more per call.
            dq = eigenpy.PartialPivLU(pin.getJointJacobian(m, d, j6, pin.LOCAL)).solve(
                pin.log6(E).vector)
            if not float(dq @ dq) < 0.04:  # also catches NaN
                return False, q, *self._tcp_error(E, tcp_offset), it
            q = q + dq
            pin.forwardKinematics(m, d, q)
            pe, re = self._tcp_error(d.oMi[j6].actInv(goal), tcp_offset)
            if pe <= pos_tol and re <= rot_tol:
                if not self._within_limits(q):  # a joint on its limit stepped just past it
                    q = np.clip(q, self._lower, self._upper)
                    pe, re = self._pose_error_of(q, goal, tcp_offset)
                    return pe <= pos_tol and re <= rot_tol, q, pe, re, it
                return True, q, pe, re, it
        return False, q, pe, re, max_steps

    def _dls(self, q0, goal: pin.SE3, tcp_offset, pos_tol, rot_tol, max_iter: int):
        """Damped least squares on log6 of the joint-6 error, clamped to the joint limits.

        Levenberg-Marquardt damping ~ |e|²: heavy far away, vanishing at the solution, so it
        still converges quickly next to a singularity. Returns like :meth:`_polish`.
        """
        m, d, j6 = self._pin, self._data(), self._joint6
        lo, hi = self._lower, self._upper
        q = np.clip(np.array(q0, dtype=float), lo, hi)
        for it in range(max_iter + 1):
            pin.computeJointJacobians(m, d, q)
            E = d.oMi[j6].actInv(goal)
            pe, re = self._tcp_error(E, tcp_offset)
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

    def _dls_restarts(self, ref, goal, tcp_offset, pos_tol, rot_tol, max_iter, restarts):
        """Damped least squares from ``ref``, then from random configurations (fixed RNG seed);
        of the successful runs the one nearest ``ref`` wins."""
        rng = np.random.default_rng(20240611)
        best_fail = (math.inf, math.inf)
        found = []
        iters = 0
        starts = [ref] + [rng.uniform(self._lower, self._upper) for _ in range(restarts)]
        for k, q0 in enumerate(starts):
            ok, q, pe, re, n = self._dls(q0, goal, tcp_offset, pos_tol, rot_tol, max_iter)
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
