"""The node's sim/snapshot service pictures the arm where it stands, before and after a move."""
from __future__ import annotations

import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.sim.snapshot import TwinCamera
from support.pictures import read_png
from support.ros_harness import at_rest

pytestmark = pytest.mark.ros


def test_node_service_pictures_the_current_pose(sim_driver, call, joints, tmp_path):
    from jaka_msgs.srv import Move
    from std_srvs.srv import Trigger

    import rospy

    rospy.set_param(sim_driver.name("snapshot_path"), str(tmp_path / "before.png"))
    before = call("sim/snapshot", Trigger)
    assert before.success, before.message
    assert str(tmp_path / "before.png") in before.message and "rad" in before.message
    target = [0.8, 1.9, -1.4, 1.1, 1.57, 0.0]
    assert call("joint_move", Move, pose=target, mvvelo=2.0, mvacc=5.0).ret == 1
    at_rest(joints)
    rospy.set_param(sim_driver.name("snapshot_path"), str(tmp_path / "after.png"))
    after = call("sim/snapshot", Trigger)
    assert after.success, after.message
    a, b = read_png(tmp_path / "before.png"), read_png(tmp_path / "after.png")
    assert a.shape == b.shape == (600, 800, 3)
    moved = np.any(np.abs(a.astype(int) - b.astype(int)) > 30, axis=2)
    assert moved.mean() > 0.01, "the second picture should show the arm where it moved to"
    # It is the pose the node reports with it (the joints in the answer), which is the
    # target of the move: rendering that pose here gives the same picture.
    q = np.array([float(v) for v in
                  after.message.rsplit("[", 1)[1].split("]", 1)[0].split(",")])
    np.testing.assert_allclose(q, target, atol=2e-3)
    with TwinCamera(load_model("zu5")) as cam:
        expected = cam.render(q)
    differs = np.any(np.abs(expected.astype(int) - b.astype(int)) > 30, axis=2).mean()
    assert differs < 0.005, f"{differs:.2%} of the pixels differ from the reported pose"
