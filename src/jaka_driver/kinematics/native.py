"""The compiled fast path of the IK (``jaka_ik.c`` beside this file), through ctypes.

:class:`jaka_driver.kinematics.Kinematics` enters it once for every IK request on a Zu-structure
chain: closed form of the nearest configuration + Newton steps, in one C call instead of
dozens of Python → Pinocchio calls. It answers only successes; anything else (no closed-form
solution, a singular spot, no convergence) goes to the Python path, which also explains
failures — without a second C call, which would only compute the same refusal again. Both
paths compute the same solution.

``make setup`` compiles the library to ``devel/lib/libjaka_ik.so``, a catkin build to the
workspace's ``devel/lib`` and ``install/lib`` (``JAKA_IK_LIB`` names another file). Without
it — a machine without a C compiler — :func:`load` answers None and the Python path does everything, only slower.

Units: m, rad. Frames: matrices are row-major 4x4 poses in the base frame (``base_link``), of
the flange (:meth:`NativeIk.solve_seeded`) or of the joint-6 frame (:meth:`NativeIk.solve`).
"""
from __future__ import annotations

import ctypes
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from ..host import native_library

LIBRARY = "libjaka_ik.so"
_DoubleP = ctypes.POINTER(ctypes.c_double)
_Joints = ctypes.c_double * 6
_Pose = ctypes.c_double * 16
_Offset = ctypes.c_double * 3
_Out = ctypes.c_double * 8
_PoseSigma = ctypes.c_double * 17


class _Chain(ctypes.Structure):
    """``jk_chain`` of jaka_ik.c, field for field (m, rad)."""

    _fields_ = [("R", (ctypes.c_double * 9) * 6), ("t", (ctypes.c_double * 3) * 6),
                ("fix6", ctypes.c_double * 12), ("tip", ctypes.c_double * 12),
                ("a2", ctypes.c_double), ("a3", ctypes.c_double), ("d4", ctypes.c_double),
                ("d5", ctypes.c_double), ("d6", ctypes.c_double),
                ("shoulder", ctypes.c_double * 3), ("lo", ctypes.c_double * 6),
                ("hi", ctypes.c_double * 6), ("w2", ctypes.c_double * 6)]


def library_path() -> Path:
    """``$JAKA_IK_LIB``, else where :func:`jaka_driver.host.native_library.path` finds it."""
    return native_library.path(LIBRARY, "JAKA_IK_LIB")


def _open(path: Path) -> Optional[ctypes.CDLL]:
    if not path.is_file():
        return None
    try:
        # PyDLL: the interpreter lock stays held through a call (a few µs): releasing and
        # taking it back costs more, and lets another thread in mid-cycle
        lib = ctypes.PyDLL(str(path))
    except OSError:
        return None
    if lib.jk_chain_size() != ctypes.sizeof(_Chain) or not hasattr(lib, "jk_tcp_sigma"):
        return None     # built from another version of jaka_ik.c: do not guess its layout
    lib.jk_ik.restype = ctypes.c_int
    lib.jk_ik.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p,
                          ctypes.c_double, ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p]
    lib.jk_ik_seeded.restype = ctypes.c_int
    lib.jk_ik_seeded.argtypes = [ctypes.c_void_p, _DoubleP, _DoubleP,
                                 ctypes.c_double, ctypes.c_double, ctypes.c_void_p]
    lib.jk_local_seeded.restype = ctypes.c_int
    lib.jk_local_seeded.argtypes = [ctypes.c_void_p, _DoubleP, _DoubleP, ctypes.c_double,
                                    ctypes.c_double, ctypes.c_int, ctypes.c_double,
                                    ctypes.c_void_p]
    lib.jk_tcp_sigma.restype = ctypes.c_int
    lib.jk_tcp_sigma.argtypes = [ctypes.c_void_p, _DoubleP, ctypes.c_void_p, ctypes.c_void_p]
    return lib


_LIB = native_library.opened(library_path(), _open, "IK library",
                             "the Python path solves the IK")


class NativeIk:
    """The compiled IK for one chain (see :func:`load`). Not thread-bound: each call has its
    own buffers, and the C code keeps no state."""

    def __init__(self, lib: ctypes.CDLL, chain: _Chain):
        self._lib = lib
        self._chain = chain          # kept alive: C reads it on every call
        self._chain_addr = ctypes.addressof(chain)

    def solve_local_seeded(self, flange, seed, pos_tol: float, rot_tol: float, steps: int,
                           radius: float):
        """As :meth:`solve_seeded`, by damped least squares from the seed (at most ``steps``
        steps, then two settling Newton steps), answered only when no joint ends more than
        ``radius`` rad from the seed: the first attempt for the structures without a compiled
        closed form (``Kinematics._ik_python`` does the same in Python)."""
        views = _views(flange, seed)
        if views is None:
            return None
        out = _Out()
        taken = self._lib.jk_local_seeded(self._chain_addr, *views, pos_tol, rot_tol, steps,
                                          radius, out)
        if taken <= 0:
            return None
        return np.frombuffer(out, count=6).copy(), out[6], out[7], taken

    def solve_seeded(self, flange, seed, pos_tol: float, rot_tol: float):
        """``(q rad, position error m, rotation error rad, Newton steps)`` for a flange pose
        (4x4, base frame) and a seed (rad, J1..J6), no tool, no user frame; None when C does
        not solve it. ``pos_tol`` (m) and ``rot_tol`` (rad) bound the TCP error.

        C checks finiteness and clamps the seed into the limits as the Python path does.
        Float64 numpy arrays go to C as they are, the cheapest call of all; anything else of
        the right shape (lists, read-only, Fortran-ordered or strided arrays) is copied first,
        so every well-formed request enters C exactly once. None without entering C when the
        shapes are wrong or the values are not numbers (the Python path refuses those)."""
        views = _views(flange, seed)
        if views is None:
            return None
        out = _Out()
        steps = self._lib.jk_ik_seeded(self._chain_addr, *views, pos_tol, rot_tol, out)
        if steps <= 0:
            return None
        return np.frombuffer(out, count=6).copy(), out[6], out[7], steps

    def tcp_sigma(self, q: np.ndarray, tool) -> Optional[tuple[np.ndarray, float]]:
        """(TCP pose 4x4 m, smallest singular value of the TCP's Jacobian) at the joints ``q``
        (rad, a float64 array of 6), ``tool`` the TCP in the joint-6 frame (a C-ordered float64
        4x4, or None); None when a joint is not finite. One C call for a velocity jog's
        per-cycle look at the arm (:meth:`jaka_driver.kinematics.Kinematics.tcp_pose_and_sigma`)."""
        try:
            joints = _Joints.from_buffer(q) if _plain(q) and q.shape == (6,) else None
        except (TypeError, ValueError, BufferError):   # read-only or not C-contiguous
            joints = None
        if joints is None:
            try:
                a = np.asarray(q, dtype=float)
            except (TypeError, ValueError):
                return None      # the caller's Python path refuses it
            if a.shape != (6,):
                return None
            joints = _Joints(*a.tolist())
        out = _PoseSigma()
        if not self._lib.jk_tcp_sigma(self._chain_addr, joints,
                                      None if tool is None else tool.ctypes.data, out):
            return None
        return np.frombuffer(out, count=16).reshape(4, 4), out[16]

    def solve(self, goal: np.ndarray, ref: Sequence[float], tcp_offset, pos_tol: float,
              rot_tol: float):
        """``(q rad, position error m, rotation error rad, Newton steps)`` or None (the Python
        path decides). ``goal``: joint-6 pose (4x4, m, base frame); ``ref``: the reference
        joints (rad, inside the limits); ``tcp_offset``: joint 6 → TCP (m, joint-6 frame) or
        None; ``pos_tol`` (m) and ``rot_tol`` (rad) bound the TCP error."""
        if not (goal.flags.c_contiguous and goal.dtype == np.float64):
            goal = np.ascontiguousarray(goal, dtype=np.float64)
        ref_buf = _Joints(*ref)
        off_buf = None if tcp_offset is None else _Offset(*tcp_offset)
        # q (6) then the errors (2): one ctypes buffer costs less than numpy outputs (each
        # numpy address lookup is ~1.4 µs, as long as the whole C solution)
        out = _Out()
        steps = self._lib.jk_ik(self._chain_addr, goal.ctypes.data, ref_buf, off_buf,
                                pos_tol, rot_tol, out, ctypes.byref(out, 48))
        if steps <= 0:
            return None
        return np.frombuffer(out, count=6).copy(), out[6], out[7], steps


_FLOAT64 = np.dtype(np.float64)


def _plain(a) -> bool:
    """A float64 numpy array, the only kind handed to C as is (``from_buffer`` then refuses
    what is not contiguous and writable). ``is``: numpy's float64 dtype is one object; a
    dtype that is not it only costs the slower path."""
    return type(a) is np.ndarray and a.dtype is _FLOAT64


def _views(flange, seed):
    """ctypes views of a flange pose (4x4) and a seed (6,): the caller's own memory when they
    are plain float64 arrays (half the cost of ndarray.ctypes.data), else of copies; None when
    the shapes are wrong or the values are not numbers."""
    if _plain(flange) and _plain(seed) and flange.shape == (4, 4) and seed.shape == (6,):
        try:
            return _Pose.from_buffer(flange), _Joints.from_buffer(seed)
        except (TypeError, ValueError, BufferError):   # read-only or not C-contiguous
            pass
    return _copied_views(flange, seed)


def _copied_views(flange, seed):
    """ctypes views of fresh float64 C-ordered copies of a flange pose (4x4) and a seed (6,),
    or None when the shapes are wrong or the values are not numbers."""
    try:
        flange = np.array(flange, dtype=np.float64, order="C")
        seed = np.array(seed, dtype=np.float64, order="C")
    except (TypeError, ValueError):
        return None
    if flange.shape != (4, 4) or seed.shape != (6,):
        return None
    return _Pose.from_buffer(flange), _Joints.from_buffer(seed)


def load(placements: Sequence[tuple[np.ndarray, np.ndarray]], fix6: np.ndarray,
         geometry, lower: np.ndarray, upper: np.ndarray,
         weight2: np.ndarray) -> Optional[NativeIk]:
    """The compiled IK of a 6-joint chain, or None when the library is not built.

    ``placements``: (rotation 3x3, translation m) of each joint in its parent joint frame,
    each joint turning about its frame's z; ``fix6``: the model's joint-6 frame in the last of
    those frames (4x4) (see :func:`.chain.z_axis_placements`); ``geometry``: the ideal Zu chain
    of the closed form (:class:`.closed_form.ZuGeometry`), or None for a chain of another
    structure (then only :meth:`NativeIk.solve_local_seeded` may be called); limits rad;
    ``weight2``: (1/max_velocity)².
    """
    if _LIB is None:
        return None
    chain = _Chain()
    for i, (rotation, translation) in enumerate(placements):
        chain.R[i][:] = np.asarray(rotation, float).reshape(9).tolist()
        chain.t[i][:] = np.asarray(translation, float).tolist()
    chain.fix6[:] = np.asarray(fix6, float)[:3].reshape(12).tolist()
    if geometry is not None:
        chain.tip[:] = np.asarray(geometry.tip, float)[:3].reshape(12).tolist()
        chain.a2, chain.a3, chain.d4, chain.d5, chain.d6 = (float(x) for x in geometry.lengths)
        chain.shoulder[:] = [float(x) for x in geometry.shoulder]
    chain.lo[:] = np.asarray(lower, float).tolist()
    chain.hi[:] = np.asarray(upper, float).tolist()
    chain.w2[:] = np.asarray(weight2, float).tolist()
    return NativeIk(_LIB, chain)
