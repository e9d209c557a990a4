"""`roslaunch jaka_driver jaka_driver.launch model:=<m>` works for every one of the 22 models: the
launch file finds the model's URDF, the node starts on its twin, answers `get_fk` with JAKA's own
chain (test/data/jaka_chains/flange_poses.json, composed without the driver: within 0.05 mm, and
1e-5 rad — GetFK carries float32, whose rounding of six joint angles alone can turn the flange by
~1e-6 rad) and moves.

One roslaunch per model on the suite's rosmaster, one after the other, each stopped before the
next starts.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from support.ros_harness import LaunchProcess, Services, position

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.common.transforms import pose_mm_to_matrix, rotation_angle_between

pytestmark = pytest.mark.ros

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "jaka_chains" / "flange_poses.json"
POSES = json.loads(FIXTURE.read_text())
NUDGE = np.array([0.2, -0.1, 0.15, 0.2, -0.2, 0.3])    # rad, a short joint_move from home


@pytest.fixture(params=MODEL_NAMES)
def launched(request, rospy_node):
    launch = LaunchProcess(log_name=f"launch_{request.param}", model=request.param)
    request.addfinalizer(launch.stop)
    launch.wait_ready()
    services = Services(launch)
    request.addfinalizer(services.close)
    return request.param, launch, services


def test_launch_starts_the_model_answers_get_fk_and_moves(launched):
    from jaka_msgs.srv import GetFK, Move
    from sensor_msgs.msg import JointState
    from support.ros_harness import Recorder
    name, launch, call = launched
    for rec in POSES[name]:
        reply = call("get_fk", GetFK, joint=rec["q"])
        assert not reply.message.startswith("error"), reply.message
        T = pose_mm_to_matrix(reply.cartesian_pose)
        assert np.linalg.norm(T[:3, 3] - rec["position_m"]) <= 0.05e-3
        assert rotation_angle_between(T[:3, :3], np.array(rec["rotation"])) <= 1e-5
    model = load_model(name)
    target = np.clip(model.home + NUDGE, model.lower, model.upper)
    reply = call("joint_move", Move, pose=target.tolist(), mvvelo=1.0, mvacc=4.0)
    assert reply.ret == 1, reply.message
    recorder = Recorder(launch.name("joint_position"), JointState)
    try:
        np.testing.assert_allclose(position(recorder), target, atol=2e-3)
    finally:
        recorder.close()
