"""Shared fixtures: one rosmaster and one rospy node for the whole run; a driver node per
test module that asks for one."""
from __future__ import annotations

import numpy as np
import pytest

from ros_harness import DriverProcess, Recorder, RosMaster, Services

#: JAKA's "pose_1": upper arm up, forearm forward, flange down — the twin's start pose (rad)
START = [0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0]


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


def start_driver(request, **params):
    driver = DriverProcess(log_name=request.module.__name__, **params)
    request.addfinalizer(driver.stop)
    driver.wait_ready()
    return driver


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


def go_home(call) -> None:
    """Leave servo mode, stop whatever moves and return to START (a test's clean slate)."""
    from jaka_msgs.srv import Move, ServoMoveEnable
    from std_srvs.srv import Empty
    from ros_harness import wait_until
    call("servo_move_enable", ServoMoveEnable, enable=False)
    call("stop_move", Empty)
    reply = wait_until(lambda: (r := call("joint_move", Move, pose=START, mvvelo=2.0,
                                          mvacc=8.0)).ret == 1 and r, 3.0, 0.2)
    assert reply, "could not return to START"


def position(recorder, timeout=2.0) -> np.ndarray:
    """Latest joint position (rad) from a JointState recorder."""
    from ros_harness import wait_until
    msg = wait_until(recorder.latest, timeout)
    assert msg is not None, "no joint_position message"
    return np.array(msg.position)


def at_rest(recorder, timeout=3.0, speed=1e-3) -> np.ndarray:
    """Joint position once every joint is slower than ``speed`` rad/s (the end of a move's
    settling), so a later comparison sees only new motion."""
    from ros_harness import wait_until
    msg = wait_until(lambda: (m := recorder.latest()) is not None
                     and np.max(np.abs(m.velocity)) < speed and m, timeout)
    assert msg, "the arm did not come to rest"
    return np.array(msg.position)
