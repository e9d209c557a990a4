"""The FollowJointTrajectory and GripperCommand types the action servers speak have control_msgs
1.5's md5 sums (follow_joint_trajectory.md), so MoveIt's trajectory execution and its gripper
controller talk to them unchanged."""
import pytest

import control_msgs.msg as cm

MD5 = {
    "JointTolerance": "f544fe9c16cf04547e135dd6063ff5be",
    "FollowJointTrajectoryGoal": "69636787b6ecbde4d61d711979bc7ecb",
    "FollowJointTrajectoryResult": "493383b18409bfb604b4e26c676401d2",
    "FollowJointTrajectoryFeedback": "10817c60c2486ef6b33e97dcd87f4474",
    "FollowJointTrajectoryActionGoal": "cff5c1d533bf2f82dd0138d57f4304bb",
    "FollowJointTrajectoryActionResult": "c4fb3b000dc9da4fd99699380efcc5d9",
    "FollowJointTrajectoryActionFeedback": "d8920dc4eae9fc107e00999cce4be641",
    "FollowJointTrajectoryAction": "bc4f9b743838566551c0390c65f1a248",
    "GripperCommand": "680acaff79486f017132a7f198d40f08",
    "GripperCommandAction": "950b2a6ebe831f5d4f4ceaba3d8be01e",
}


@pytest.mark.parametrize("name", MD5)
def test_md5_matches_control_msgs(name):
    assert getattr(cm, name)._md5sum == MD5[name]


def test_result_codes_are_joint_trajectory_controllers():
    r = cm.FollowJointTrajectoryResult
    assert (r.SUCCESSFUL, r.INVALID_GOAL, r.INVALID_JOINTS, r.PATH_TOLERANCE_VIOLATED,
            r.GOAL_TOLERANCE_VIOLATED) == (0, -1, -2, -4, -5)
