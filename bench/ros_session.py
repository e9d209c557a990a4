"""The ROS side of the benchmarks, on the test harness (``test/support/ros_harness.py``): a private
rosmaster on a free port, this process as a rospy node, and the driver node as a subprocess.

Everything started here is registered on a :class:`contextlib.ExitStack`, so it is stopped
even when a measurement fails.
"""
from __future__ import annotations

import sys
from contextlib import ExitStack
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "test") not in sys.path:
    sys.path.insert(0, str(ROOT / "test"))


from support.ros_harness import (DriverProcess, Recorder, RosMaster, Services,  # noqa: E402,F401
                                 forget_sim_time, stop_process, wait_until)


def start_ros(stack: ExitStack) -> RosMaster:
    """A rosmaster (``ROS_*`` variables point at it from now on) and this process as node
    ``/jaka_bench``; both end with ``stack``."""
    master = RosMaster()
    stack.callback(master.stop)
    import rospy
    rospy.init_node("jaka_bench", anonymous=True, disable_signals=True)
    stack.callback(rospy.signal_shutdown, "benchmarks done")
    return master


def start_driver(stack: ExitStack, log_name: str, timeout: float = 60.0,
                 **params) -> DriverProcess:
    """The driver node with private ``params`` (``backend``, ``model``...), ready to serve."""
    driver = DriverProcess(log_name=log_name, **params)
    stack.callback(driver.stop)
    driver.wait_ready(timeout)
    return driver


def services(stack: ExitStack, driver: DriverProcess) -> Services:
    """Persistent proxies to ``driver``'s services, closed with ``stack``."""
    calls = Services(driver)
    stack.callback(calls.close)
    return calls


def recorder(stack: ExitStack, topic: str, msg_type) -> Recorder:
    rec = Recorder(topic, msg_type)
    stack.callback(rec.close)
    return rec


