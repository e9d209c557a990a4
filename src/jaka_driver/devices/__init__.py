"""Devices on the arm built above the backends (docs/design.md, "Where a new capability
lives"): a gripper's register map spoken over the tool connector's frames and signals, the same
code on the twin and on a controller."""
from .gripper import ConnectorSetup, GripperState, ModbusGripper
from .modbus_frames import read_request, write_register
from .register_maps import DH_FIGURES, DH_PGI, FIGURES, MAPS, GripperFigures, GripState, RegisterMap

__all__ = ["ConnectorSetup", "DH_FIGURES", "DH_PGI", "FIGURES", "GripState", "GripperFigures",
           "GripperState", "MAPS", "ModbusGripper", "RegisterMap", "read_request",
           "write_register"]
