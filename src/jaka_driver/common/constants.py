"""Numbers every layer of the driver shares, defined once.

The JAKA controller runs an 8 ms cycle: a servo set-point is meant for one cycle, the status
stream publishes once per cycle, and the twin plans and steps its drives on the same cycle.
"""
from __future__ import annotations

import math

#: s — the controller cycle: servo set-point period, status period, the twin's control cycle
SERVO_CYCLE = 0.008

#: cycles behind its pacing after which a paced loop (the twin's physics on the wall clock, the
#: sim clock at a real-time factor) re-anchors instead of bursting through the missed cycles
STALL_CYCLES = 25

#: rad/s and rad/s² — the fastest the driver turns the tool about its own axes: a rotation jog
#: (RX–RZ; a faster request is clamped to it) and the orientation of a straight line (both
#: backends; :func:`jaka_driver.motion.linear_path.orientation_limits`)
MAX_TOOL_ROTATION_SPEED = math.pi
MAX_TOOL_ROTATION_ACCEL = 2.0 * math.pi

#: rad — a joint move is in position once every joint is this close to its target
#: (docs/interface.md, "Motion")
IN_POSITION = 1e-3

#: A started move may take ``MOVE_OVERRUN_FACTOR`` × its planned duration plus
#: ``MOVE_OVERRUN_MARGIN`` s before the driver stops it and answers -12. The factor covers a
#: controller that plans its own (slower) profile; the margin covers settling and a short move
#: whose plan is a few cycles.
MOVE_OVERRUN_FACTOR = 1.5
MOVE_OVERRUN_MARGIN = 2.0   # s


def move_deadline(planned_duration: float) -> float:
    """How long (s) the driver waits for a move planned to take ``planned_duration`` s."""
    return MOVE_OVERRUN_FACTOR * planned_duration + MOVE_OVERRUN_MARGIN
