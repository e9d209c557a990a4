"""Fixtures of the ROS tests: one rosmaster and one rospy node for the whole run; a driver node
per test module that asks for one."""
from __future__ import annotations

import pytest

from support.ros_harness import (Recorder, RosMaster, Services, delivers_to_us, start_driver,
                                 wait_until)


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
    yield from _recording(sim_driver, "joint_position", JointState)


@pytest.fixture(scope="module")
def tcp(sim_driver, rospy_node):
    from geometry_msgs.msg import TwistStamped
    yield from _recording(sim_driver, "tool_position", TwistStamped)


@pytest.fixture(scope="module")
def states(sim_driver, rospy_node):
    from jaka_msgs.msg import RobotMsg
    yield from _recording(sim_driver, "robot_states", RobotMsg)


def _recording(driver, topic: str, msg_class):
    """A module's recorder of one of the driver's topics, closed after the module; it gets
    every message from the fixture's end on (the node has it among its subscribers: a paused
    twin publishes nothing until stepped, so a sample sent before would never come again)."""
    recorder = Recorder(driver.name(topic), msg_class)
    assert wait_until(lambda: delivers_to_us(driver, topic), 30.0), \
        f"{driver.name(topic)}: the node has not connected this test process in 30 s"
    yield recorder
    recorder.close()
