"""Kinematics of the JAKA arms: FK, Jacobian and IK on Pinocchio, in m and rad.

* :mod:`.model` — what the robot is: the Pinocchio model, FK, Jacobian, frames (base, flange,
  tool, user) and the IK dispatch, the structure's solver first, numeric fallback;
* :mod:`.chain` — the nominal chain as geometry (joint frames, axes at q = 0) in plain numpy;
* :mod:`.closed_form` — the up-to-8 solutions of the ideal Zu-structure (UR-type) chain;
* :mod:`.spherical_wrist` — the up-to-8 solutions of a spherical-wrist chain (MiniCobo);
* :mod:`.forearm_roll` — every solution of the A12's forearm-roll chain, by a 1-D search;
* :mod:`.arm_plane` — J1 … J3 placing a wrist point, for those two; :mod:`.branches` — the
  nearest 2π-turn inside the limits and the ordering of solutions;
* :mod:`.native` — the Zu closed form + Newton, and the damped least squares from the seed,
  compiled (``jaka_ik.c``), through ctypes;
* :mod:`.numeric` — Newton polish, damped least squares and restarts on the exact model;
* :mod:`.controller_dh` — the chain as a JAKA controller states it (``get_dh_param``, modified
  DH), derived from a model and compared with another;
* :mod:`.calibrated_chain` — a model rebuilt on such parameters (a calibrated arm, another
  arm's chain), and a plausible calibration of a parameter set.
"""
from .model import IkResult, Kinematics

__all__ = ["IkResult", "Kinematics"]
