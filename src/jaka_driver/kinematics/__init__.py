"""Kinematics of the JAKA Zu arms: FK, Jacobian and IK on Pinocchio, in m and rad.

* :mod:`.model` — what the robot is: the Pinocchio model, FK, Jacobian, frames (base, flange,
  tool, user) and the IK dispatch, closed form first, numeric fallback;
* :mod:`.closed_form` — the up-to-8 solutions of the ideal UR-type chain;
* :mod:`.native` — the same closed form + Newton compiled (``jaka_ik.c``), through ctypes;
* :mod:`.numeric` — Newton polish, damped least squares and restarts on the exact model;
* :mod:`.controller_dh` — the chain as a JAKA controller states it (``get_dh_param``, modified
  DH), derived from a model and compared with another.
"""
from .model import IkResult, Kinematics

__all__ = ["IkResult", "Kinematics"]
