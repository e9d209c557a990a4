"""Where JAKA's interface document and JAKA's own driver code disagree, and how the driver reads
each side (``~conventions``: ``document``, the default, or ``jaka_code``).

* :mod:`.choice` — :class:`Conventions`, the two sets :data:`DOCUMENT` and :data:`JAKA_CODE`
  (the table of every difference), :func:`conventions_named`;
* :mod:`.cartesian` — a pose of linear_move / get_ik / get_fk, mm + rotation vector or RPY,
  and the note a document-mode answer carries when the two readings are far apart;
* :mod:`.jog_speed` — a jog's speed from ``mvvelo`` or ``mvacc``;
* :mod:`.servo_increments` — servo_j / servo_p read as increments of the last target.

Plain Python below the node: RobotDriver applies the requests' conventions; the node only
chooses the messages of the two topics that differ (tool_position, robot_states.servo_state).
"""
from .choice import DOCUMENT, JAKA_CODE, NAMES, Conventions, conventions_named
from .servo_increments import ServoIncrements

__all__ = ["Conventions", "DOCUMENT", "JAKA_CODE", "NAMES", "conventions_named",
           "ServoIncrements"]
