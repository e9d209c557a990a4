"""The two sets of conventions the driver can read its requests and write its answers in.

JAKA's interface document (V2.2) and JAKA's own driver code (jaka_robot v2.2,
``jaka_driver.cpp``, the code most existing JAKA ROS programs were written against) disagree in
five places. ``~conventions`` chooses one side for all of them at once:

==============================  ===================================  ==================================
                                ``document`` (default)               ``jaka_code``
==============================  ===================================  ==================================
servo_j / servo_p               absolute targets; servo_p m + RPY    increments of the last target;
                                                                     servo_p mm + RPY rad
linear_move, get_ik (request),  mm + rotation vector (rad)           mm + RPY rad (JAKA's code since
get_fk (answer) orientation                                          2025-04 passes them to the SDK
                                                                     as they are)
linear_move coord_mode,         honoured (user / base / tool;        not read (JAKA's code passes
has_ref / ref_joint             IK seed)                             neither to the SDK)
jog speed                       ``mvvelo`` (``mvacc`` when mvvelo    ``mvacc`` (JAKA's code reads
                                is 0)                                only mvacc)
robot_states.servo_state        servo mode on                        robot enabled
tool_position                   TwistStamped, m + rotation vector    PoseStamped, mm + quaternion
                                                                     (JAKA's code since 2025-06)
==============================  ===================================  ==================================

set_toolframe / set_userframe take mm + rotation vector in both (JAKA's code converts them from
a rotation vector too); FollowJointTrajectory, joint_move and the other services are the same
in both. ``servo_increment`` stays the finer control: it adds increments to ``document``, and
``jaka_code`` implies it.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

ROTATION_VECTOR = "rotation vector"
RPY = "RPY"


@dataclass(frozen=True)
class Conventions:
    """How the driver reads requests and writes answers (see the module's table).

    ``cartesian_rotation``: how the orientation of linear_move's and get_ik's pose and of
    get_fk's answer is read (:data:`ROTATION_VECTOR` or :data:`RPY`, rad; positions mm in both).
    ``linear_move_frame_fields``: linear_move's coord_mode and has_ref/ref_joint are honoured.
    ``servo_increment``: servo_j / servo_p take increments. ``jog_speed_field``: the Move field
    a jog's speed is read from (``mvvelo``, falling back to ``mvacc`` when it is 0, or ``mvacc``
    only). ``servo_state_is_enabled``: robot_states.servo_state says "robot enabled" instead of
    "servo mode on". ``tool_position_pose``: tool_position is a PoseStamped in mm + quaternion
    instead of a TwistStamped in m + rotation vector."""
    name: str
    cartesian_rotation: str
    linear_move_frame_fields: bool
    servo_increment: bool
    jog_speed_field: str
    servo_state_is_enabled: bool
    tool_position_pose: bool

    def with_servo_increment(self, on: bool) -> "Conventions":
        """These conventions, servo_j / servo_p taking increments if ``on`` (or already)."""
        if self.servo_increment or not on:
            return self
        return replace(self, name=f"{self.name} + servo_increment", servo_increment=True)

    def describe(self) -> str:
        """One line for the start-up log and /diagnostics."""
        servo = "increments" if self.servo_increment else "absolute targets"
        tool = ("PoseStamped mm + quaternion" if self.tool_position_pose
                else "TwistStamped m + rotation vector")
        state = "robot enabled" if self.servo_state_is_enabled else "servo mode"
        return (f"{self.name}: linear_move/get_ik/get_fk orientation {self.cartesian_rotation}, "
                f"servo_j/servo_p {servo}, jog speed {self.jog_speed_field}, tool_position "
                f"{tool}, robot_states.servo_state = {state}")


#: JAKA's interface document V2.2, the driver's default
DOCUMENT = Conventions(name="document", cartesian_rotation=ROTATION_VECTOR,
                       linear_move_frame_fields=True, servo_increment=False,
                       jog_speed_field="mvvelo", servo_state_is_enabled=False,
                       tool_position_pose=False)
#: JAKA's driver code (jaka_robot v2.2 jaka_driver.cpp, 2025-06)
JAKA_CODE = Conventions(name="jaka_code", cartesian_rotation=RPY,
                        linear_move_frame_fields=False, servo_increment=True,
                        jog_speed_field="mvacc", servo_state_is_enabled=True,
                        tool_position_pose=True)
NAMES = (DOCUMENT.name, JAKA_CODE.name)


def conventions_named(name: str) -> Conventions:
    """``document`` or ``jaka_code`` (ValueError naming both otherwise)."""
    for conventions in (DOCUMENT, JAKA_CODE):
        if conventions.name == str(name).strip().lower():
            return conventions
    raise ValueError(f"unknown conventions {name!r}; expected one of {', '.join(NAMES)}")
