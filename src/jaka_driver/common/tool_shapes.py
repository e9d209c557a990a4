"""The shapes of the tools the twin can carry on its flange, one source for MuJoCo's bodies
(sim/gripper.py, sim/suction.py) and the URDF the node describes the arm with
(:mod:`.tool_urdf`). Flange frame: z out of the flange along the tool axis, the fingers closing
along y. Units: m, kg, N, s.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..devices.register_maps import DH_FIGURES, GripperFigures


@dataclass(frozen=True)
class GripperSpec:
    """The twin's parallel gripper: the published figures (m, N, s, kg) and its shapes."""

    figures: GripperFigures = DH_FIGURES
    finger_mass: float = 0.05        # kg, each finger with its pad
    housing: tuple = (0.035, 0.065, 0.045)    # half-sizes, flange x y z; its base on the flange
    pad: tuple = (0.012, 0.002, 0.018)        # half-sizes; the inner face is the grip
    grasp_z: float = 0.125           # m along the flange's z: the pads' centre, the grasp point
    pad_friction: float = 1.0
    kp: float = 20000.0              # N/m, a finger's position loop (a stall pushes with the limit)
    armature: float = 0.5            # kg, the drive's inertia reflected to a finger

    @property
    def stroke(self) -> float:
        return self.figures.stroke

    @property
    def mass(self) -> float:
        return self.figures.mass

    @property
    def force_max(self) -> float:
        return self.figures.force_max

    @property
    def travel(self) -> float:
        """One finger's travel (m)."""
        return self.stroke / 2.0

    @property
    def max_speed(self) -> float:
        """One finger's speed at 100 % (m/s)."""
        return self.travel / self.figures.stroke_time

    def force(self, percent: float) -> float:
        """N per jaw at ``percent`` (20–100 %, the register's range)."""
        return self.figures.force(percent)


GRIPPER = GripperSpec()


@dataclass(frozen=True)
class SuctionSpec:
    """The suction cup: a stem and a cup whose face is the grasp point."""

    mass: float = 0.3                 # kg, the cup, its stem and the vacuum generator
    stem: tuple = (0.02, 0.04)        # m, radius and half-length along the flange's z
    cup: tuple = (0.025, 0.005)       # m, radius and half-height of the cup

    @property
    def grasp_z(self) -> float:
        """The cup's face along the flange's z (m)."""
        return 2 * (self.stem[1] + self.cup[1])


SUCTION = SuctionSpec()
