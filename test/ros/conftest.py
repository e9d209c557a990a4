"""Fixtures of the ROS tests: one rosmaster and one rospy node for the whole run; a driver node
per test module that asks for one."""
from __future__ import annotations

import pytest

from ros_harness import Recorder, RosMaster, Services, start_driver


@pytest.fixture(scope="session")
def ros_master():
    master = RosMaster()
    yield master
    master.stop()


@pytest.fixture(scope="session")
def rospy_node(ros_master):
    import rospy
    rospy.init_node("jaka_driver_tests", anonymous=True, disable_signals=True)
    yield rospy


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):
    """The real node on the zu5 twin (module-scoped: a module's tests share one arm)."""
    return start_driver(request, backend="sim", model="zu5")


@pytest.fixture(scope="module")
def call(sim_driver):
    services = Services(sim_driver)
    yield services
    services.close()


@pytest.fixture(scope="module")
def joints(sim_driver, rospy_node):
    from sensor_msgs.msg import JointState
    recorder = Recorder(sim_driver.name("joint_position"), JointState)
    yield recorder
    recorder.close()


@pytest.fixture(scope="module")
def tcp(sim_driver, rospy_node):
    from geometry_msgs.msg import TwistStamped
    recorder = Recorder(sim_driver.name("tool_position"), TwistStamped)
    yield recorder
    recorder.close()


@pytest.fixture(scope="module")
def states(sim_driver, rospy_node):
    from jaka_msgs.msg import RobotMsg
    recorder = Recorder(sim_driver.name("robot_states"), RobotMsg)
    yield recorder
    recorder.close()
