"""The scene's parts and the gripper's door through ROS, on one node: the zu5 twin with the
suction cup mounted (``_gripper:=suction``) over config/scenes/pick.yaml's table and box.

The box is on ``~sim/parts`` and in TF as a frame ``box`` where the scene put it (resting on
the table); ``~sim/reset`` puts it back at the scene's pose. The gripper's services and its
GripperCommand action are served on every node: with no register-map gripper (a suction cup is
switched by a tool DO) every request answers -9 saying how to mount one, and a goal is
aborted with that reason."""
import actionlib
import numpy as np
import pytest
import rospy
import tf2_ros
from control_msgs.msg import GripperCommandAction, GripperCommandGoal
from tf2_msgs.msg import TFMessage

from jaka_driver.common.models import repo_root
from jaka_driver_msgs.srv import InitGripper, ResetTwin, SetGripperPercent
from support.ros_harness import Recorder, action_done, start_driver, wait_until

pytestmark = pytest.mark.ros

SCENE_POSE = np.array([0.482, 0.114, 0.23])         # m, the box as the scene places it
RESTING_Z = 0.23                                     # m, on the table top (0.20) + 0.03
#: m, how far the box sinks into the table at rest (MuJoCo's soft contact: 0.1 mm) and the
#: scene's placement's resolution
REST_TOLERANCE = 0.0005


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):   # conftest's call talks to this node
    return start_driver(request, backend="sim", model="zu5", gripper="suction",
                        scene=str(repo_root() / "config" / "scenes" / "pick.yaml"))


@pytest.fixture(scope="module")
def parts(sim_driver):
    recorder = Recorder(sim_driver.name("sim/parts"), TFMessage)
    yield recorder
    recorder.close()


def box_position(msg: TFMessage) -> np.ndarray:
    (t,) = [t for t in msg.transforms if t.child_frame_id == "box"]
    assert t.header.frame_id == "base_link"
    v = t.transform.translation
    return np.array([v.x, v.y, v.z])


def test_the_box_is_on_the_parts_topic_and_in_tf_where_it_rests(sim_driver, parts):
    msg = wait_until(parts.latest, 5.0)
    assert np.allclose(box_position(msg)[:2], SCENE_POSE[:2], atol=0.001)
    assert box_position(msg)[2] == pytest.approx(RESTING_Z, abs=REST_TOLERANCE)
    buffer = tf2_ros.Buffer()
    listener = tf2_ros.TransformListener(buffer)
    try:
        t = buffer.lookup_transform("base_link", "box", rospy.Time(0), rospy.Duration(5.0))
    finally:
        listener.unregister()
    v = t.transform.translation
    assert np.allclose([v.x, v.y, v.z], [*SCENE_POSE[:2], RESTING_Z], atol=0.001)


def test_the_twins_reset_puts_the_box_back_where_the_scene_placed_it(call, parts):
    assert call("sim/reset", ResetTwin, joints=[]).ret == 1
    parts.clear()
    first = box_position(wait_until(parts.latest, 5.0))      # 40 ms after the reset at most
    assert np.allclose(first, SCENE_POSE, atol=REST_TOLERANCE)


def test_without_a_gripper_its_services_and_action_refuse_with_how_to_mount_one(sim_driver, call):
    for reply in (call("gripper/initialise", InitGripper, full_calibration=False),
                  call("gripper/set_force", SetGripperPercent, percent=50),
                  call("gripper/set_speed", SetGripperPercent, percent=50)):
        assert reply.ret == -9 and "gripper:=dh_pgi" in reply.message, reply
    client = actionlib.SimpleActionClient(sim_driver.name("gripper/gripper_action"),
                                          GripperCommandAction)
    assert client.wait_for_server(rospy.Duration(5.0))
    goal = GripperCommandGoal()
    goal.command.position, goal.command.max_effort = 0.02, 50.0
    client.send_goal(goal)
    assert action_done(client, 5.0)
    assert client.get_state() == actionlib.GoalStatus.ABORTED
    assert "gripper:=dh_pgi" in client.get_goal_status_text()
