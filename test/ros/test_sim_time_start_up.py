"""Who may own ROS time at start-up: a twin asked for sim_time while another live node
publishes /clock (a second twin, rosbag play --clock, a simulator) refuses to start, names that
node and leaves /use_sim_time alone (two clocks would move ROS time each their own way); the
controller backend asked for sim_time runs on the wall clock and leaves /use_sim_time unset
(set, with nobody publishing /clock, every client's rospy.sleep would wait forever)."""
import pytest
from rosgraph_msgs.msg import Clock

from support.ros_harness import DriverProcess, free_port, start_driver, wait_until

pytestmark = pytest.mark.ros


def clock_publishers(rospy) -> list:
    import rosgraph
    publishers = dict(rosgraph.Master(rospy.get_name()).getSystemState()[0])
    return publishers.get("/clock", [])


def test_a_twin_does_not_start_a_second_clock(request, rospy_node):
    rospy = rospy_node
    other = rospy.Publisher("/clock", Clock, queue_size=1)
    request.addfinalizer(other.unregister)
    assert wait_until(lambda: rospy.get_name() in clock_publishers(rospy), 10.0)
    use_sim_time_before = rospy.get_param("/use_sim_time", None)

    driver = DriverProcess(log_name="second_clock", backend="sim", model="zu5",
                           sim_time="true", real_time_factor=0)
    request.addfinalizer(driver.stop)

    assert wait_until(lambda: not driver.alive(), 60.0), "the twin started anyway"
    assert driver.proc.returncode == 2, driver.log()
    log = driver.log()
    assert f"{rospy.get_name()} already publishes /clock" in log, log
    assert "jaka_driver ready" not in log
    assert rospy.get_param("/use_sim_time", None) == use_sim_time_before
    assert clock_publishers(rospy) == [rospy.get_name()]


def test_the_controller_backend_leaves_ros_time_on_the_wall_clock(request, rospy_node):
    rospy = rospy_node
    use_sim_time_before = rospy.get_param("/use_sim_time", None)
    # No controller listens on these ports: the node starts anyway and keeps retrying.
    driver = start_driver(request, backend="controller", ip="127.0.0.1",
                          command_port=free_port(), status_port=free_port(), sim_time="true")
    assert "~sim_time applies to the twin only" in driver.log(), driver.log()
    assert rospy.get_param("/use_sim_time", None) == use_sim_time_before
    assert "/clock" not in dict(rospy.get_published_topics())
