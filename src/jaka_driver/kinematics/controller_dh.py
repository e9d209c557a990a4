"""The arm's kinematic parameters as a JAKA controller states them (``get_dh_param``), and the
same parameters computed from a model's URDF chain.

The controller's convention is **modified DH** (Craig): from frame i-1 to frame i the transform
is ``RotX(alpha[i-1]) · TransX(a[i-1]) · RotZ(q[i] + joint_homeoff[i]) · TransZ(d[i])``, with
``alpha`` and ``a`` listed from frame 0 (arrays index 0..5 = alpha_0..alpha_5), ``d`` and
``joint_homeoff`` per joint. On the wire (docs/protocol.md, "Kinematic parameters") ``dh_param``
is four rows of six: alpha deg, a mm, d mm, joint_homeoff deg.

Why this convention: JAKA's SDK places a2, a3 at indices 2 and 3 and the 90° twists at indices 1
and 4 (alpha_{i-1}, a_{i-1} — modified DH), its alpha row for a Zu arm reads
[0, 90, 0, 0, 90, -90], and a Zu 5's parameters read from a real controller by a third-party
project have d4 negative (-114.195 mm). With exactly those choices and joint_homeoff all zero the
chain equals JAKA's URDF of each Zu arm to a few µm, frame 6 coinciding with the flange frame —
JAKA's joint zero and directions are the controller's. :func:`dh_of_model` derives the parameters
of any 6R chain by the same rules (below), so a Zu arm comes out in exactly that form.

Frames: frame 0 lies on joint 1's axis with the base's orientation (the URDF base may sit a
fraction of a mm off that axis — :attr:`ChainFit.base_offset`); frame 6 is the flange. Units in
:class:`DHParameters` are SI (rad, m).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Iterable, NamedTuple, Sequence

import numpy as np

from ..common.models import MODEL_NAMES, RobotModel, load_model
from .chain import axes_at_zero

#: Worst flange-position difference (m) between two parameter sets, over :data:`_SAMPLES`, that
#: a calibration of one arm can explain. A calibrated Zu 5 (parameters read from a real
#: controller by a third-party project) differs from the nominal chain by 1.6 mm; two JAKA models
#: that are not sold as the same arm differ by 10 mm (Zu 5 / S5, d6 +10.5 mm) or far more.
CALIBRATION_TOLERANCE = 0.005

_EPS = 1e-9
# A fixed spread of joint vectors (rad) over which two chains are compared: deterministic, so
# a comparison logged at start-up is the same number every time.
_SAMPLES = np.random.default_rng(20261124).uniform(-np.pi, np.pi, (200, 6))


@dataclass(frozen=True, eq=False)
class DHParameters:
    """Modified-DH parameters in SI: ``alpha`` rad, ``a`` m, ``d`` m, ``joint_homeoff`` rad,
    each (6,) and read-only."""

    alpha: np.ndarray
    a: np.ndarray
    d: np.ndarray
    joint_homeoff: np.ndarray

    def __post_init__(self) -> None:
        for name in ("alpha", "a", "d", "joint_homeoff"):
            v = np.array(getattr(self, name), dtype=float)
            if v.shape != (6,) or not np.all(np.isfinite(v)):
                raise ValueError(f"DH {name} must be 6 finite numbers; got {getattr(self, name)!r}")
            v[np.abs(v) < 1e-12] = 0.0   # rounding dust (and -0.0) would reach the wire
            v.setflags(write=False)
            object.__setattr__(self, name, v)

    @classmethod
    def from_sdk(cls, alpha_rad: Sequence[float], a_mm: Sequence[float], d_mm: Sequence[float],
                 homeoff_rad: Sequence[float]) -> "DHParameters":
        """From JAKA SDK units (rad, mm) — what the protocol library decodes."""
        return cls(np.asarray(alpha_rad, float), np.asarray(a_mm, float) / 1000.0,
                   np.asarray(d_mm, float) / 1000.0, np.asarray(homeoff_rad, float))

    def to_wire(self) -> list:
        """The ``dh_param`` rows of the wire: alpha deg, a mm, d mm, joint_homeoff deg."""
        return [np.degrees(self.alpha).tolist(), (self.a * 1000.0).tolist(),
                (self.d * 1000.0).tolist(), np.degrees(self.joint_homeoff).tolist()]

    def describe(self) -> str:
        """One line for a log: the wire's units."""
        rows = self.to_wire()
        return "; ".join(f"{name} [{', '.join(f'{v:.3f}' for v in row)}]" for name, row in
                         zip(("alpha deg", "a mm", "d mm", "joint_homeoff deg"), rows))


class ChainFit(NamedTuple):
    """A model's chain in the controller's convention, and what the convention cannot hold."""

    dh: DHParameters
    base_offset: np.ndarray
    """4x4 (m): frame 0 of the DH chain in the URDF base frame (a translation onto joint 1's
    axis; identity when the base sits on it)"""
    flange_offset: np.ndarray
    """4x4 (m): the URDF flange in DH frame 6 (identity when they coincide)"""


def _rot_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def dh_frames(dh: DHParameters, q: Iterable[float]) -> list:
    """4x4 (m): frames 1..6 in frame 0 at joints ``q`` (rad), by the controller's convention;
    frame i turns about joint i's axis (its z) and frame 6 is the flange."""
    q = np.asarray(q, dtype=float)
    T = np.eye(4)
    frames = []
    for i in range(6):
        theta = q[i] + dh.joint_homeoff[i]
        ct, st = np.cos(theta), np.sin(theta)
        ca, sa = np.cos(dh.alpha[i]), np.sin(dh.alpha[i])
        step = np.array([[ct, -st, 0.0, dh.a[i]],
                         [st * ca, ct * ca, -sa, -sa * dh.d[i]],
                         [st * sa, ct * sa, ca, ca * dh.d[i]],
                         [0.0, 0.0, 0.0, 1.0]])
        T = T @ step
        frames.append(T)
    return frames


def flange_pose(dh: DHParameters, q: Iterable[float]) -> np.ndarray:
    """4x4 (m): frame 6 (the flange) in frame 0 at joints ``q`` (rad), by the controller's
    convention."""
    return dh_frames(dh, q)[-1]


def chain_difference(dh: DHParameters, other: "DHParameters | RobotModel") -> float:
    """Worst flange-position difference (m) between ``dh`` and ``other`` (parameters, or a
    model's own chain) over a fixed spread of joint vectors. Compare with
    :data:`CALIBRATION_TOLERANCE`."""
    ref = other if isinstance(other, DHParameters) else dh_of_model(other)
    return max(float(np.linalg.norm(flange_pose(dh, q)[:3, 3] - flange_pose(ref, q)[:3, 3]))
               for q in _SAMPLES)


def nearest_models(dh: DHParameters) -> list:
    """``(name, difference m)`` of every model of :data:`~jaka_driver.common.models.MODEL_NAMES`,
    nearest chain to ``dh`` first (:func:`chain_difference`). Models JAKA sells with one chain
    (Zu 5, C5, Pro 5) come out at the same difference."""
    return sorted(((name, chain_difference(dh, _named_dh(name))) for name in MODEL_NAMES),
                  key=lambda row: row[1])


@functools.lru_cache(maxsize=None)
def _named_dh(name: str) -> DHParameters:
    return dh_of_model(load_model(name))


def dh_of_model(model: RobotModel) -> DHParameters:
    """``model``'s URDF chain in the controller's convention (see :func:`fit_chain`)."""
    return fit_chain(model).dh


def fit_chain(model: RobotModel) -> ChainFit:
    """Modified-DH parameters of ``model``'s chain, from its joint axes at q = 0.

    The rules, which give JAKA's own form for a Zu arm: frame i's z is joint i's axis (its URDF
    direction, so joint angles are the model's); its origin is where the common normal to the
    next axis meets it, or, where the next axis is parallel (the normal is not unique), where
    the previous normal meets it (d = 0); its x runs along that normal, of the two directions the
    one closer to the previous frame's x, so joint_homeoff stays near zero. Frame 0 takes the
    base's orientation on joint 1's axis; frame 6's x is the flange's x, its origin where the
    flange's origin projects onto joint 6's axis.
    """
    joint_axes, flange = axes_at_zero(model.chain)
    if len(joint_axes) != 6:
        raise ValueError(f"{model.name}: {len(joint_axes)} revolute joints, expected 6")
    points = [axis.point for axis in joint_axes]
    axes = [axis.direction for axis in joint_axes]

    if np.linalg.norm(np.cross(axes[0], [0.0, 0.0, 1.0])) > 1e-6:
        raise ValueError(f"{model.name}: joint 1's axis is not the base's z axis; the "
                         "controller's convention needs it to be")
    # Frame 0: the base's orientation, moved (perpendicular to z) onto joint 1's axis.
    z_prev, x_prev = axes[0], np.array([1.0, 0.0, 0.0])
    o_prev = points[0] - axes[0] * (points[0] @ axes[0])
    base = np.eye(4)
    base[:3, 3] = o_prev
    alpha, a, d, home = np.zeros(6), np.zeros(6), np.zeros(6), np.zeros(6)
    alpha[0] = 0.0   # z0 = z1 by construction
    # Where the previous normal meets axis 1: frame 0's origin lies on it.
    meet = o_prev
    for i in range(6):
        z = axes[i]
        if i < 5:
            o, x = _normal_to_next(points[i], z, points[i + 1], axes[i + 1], meet, x_prev)
        else:
            fx = flange[:3, 0] - z * (flange[:3, 0] @ z)
            if np.linalg.norm(fx) < 1e-6:
                raise ValueError(f"{model.name}: the flange's x is along joint 6's axis")
            x = fx / np.linalg.norm(fx)
            o = points[i] + z * ((flange[:3, 3] - points[i]) @ z)
        d[i] = (o - meet) @ z
        home[i] = np.arctan2(np.cross(x_prev, x) @ z, x_prev @ x)
        if i < 5:
            z_next = axes[i + 1]
            alpha[i + 1] = np.arctan2(np.cross(z, z_next) @ x, z @ z_next)
            # the next normal's foot on axis i+1 (the line through o along x meets it)
            meet, a[i + 1] = _along_normal(o, x, points[i + 1], z_next)
        z_prev, x_prev, o_prev = z, x, o
    dh = DHParameters(alpha, a, d, home)
    # What the convention cannot hold: the URDF flange in frame 6 (frame 6 in frame 0, placed
    # in the base by ``base``).
    frame6 = base @ flange_pose(dh, np.zeros(6))
    flange_offset = np.linalg.inv(frame6) @ flange
    return ChainFit(dh, base, flange_offset)


def _normal_to_next(p: np.ndarray, z: np.ndarray, p_next: np.ndarray, z_next: np.ndarray,
                    meet: np.ndarray, x_prev: np.ndarray):
    """Origin on axis (p, z) and x direction of the common normal to axis (p_next, z_next)."""
    n = np.cross(z, z_next)
    if np.linalg.norm(n) < 1e-9:   # parallel: the normal through where the last one met
        o = meet
        w = p_next - o
        w = w - z * (w @ z)
        if np.linalg.norm(w) < 1e-9:   # the same line: keep the previous x
            w = x_prev - z * (x_prev @ z)
        x = w / np.linalg.norm(w)
    else:
        # foot points of the common normal
        w0 = p - p_next
        b = z @ z_next
        denom = 1.0 - b * b
        t = (b * (z_next @ w0) - (z @ w0)) / denom
        o = p + t * z
        x = n / np.linalg.norm(n)
        if x @ x_prev < 0:
            x = -x
    return o, x


def _along_normal(o: np.ndarray, x: np.ndarray, p_next: np.ndarray, z_next: np.ndarray):
    """Where the line through ``o`` along ``x`` meets axis (p_next, z_next), and the distance
    ``a`` along ``x`` to it."""
    # the point on axis i+1 closest to the line o + s x (they meet by construction)
    w = o - p_next
    b = x @ z_next
    denom = 1.0 - b * b
    s = (b * (z_next @ w) - (x @ w)) / denom if denom > 1e-12 else -(x @ w)
    t = (z_next @ (o + s * x - p_next))
    return p_next + t * z_next, s


__all__ = ["CALIBRATION_TOLERANCE", "ChainFit", "DHParameters", "chain_difference",
           "dh_frames", "dh_of_model", "fit_chain", "flange_pose", "nearest_models"]
