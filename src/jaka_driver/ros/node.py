"""``jaka_driver_node``: the ROS adapter around a backend.

Parameters (private, ``~name``):
  ``backend``        ``sim`` (MuJoCo twin, default) or ``controller`` (JAKA TCP protocol)
  ``model``          ``zu3``, ``zu5`` (default), ``zu7``, ``zu12``, ``zu18``
  ``rate``           state publishing rate, Hz (default 125, the controller's cycle)
  ``ip``             controller address (controller backend; default 10.5.5.100)
  ``command_port``   controller command port (default 10001)
  ``status_port``    controller status port (default 10000)
  ``jog_timeout``    s after the last jog call before the jog stops (default 3.0)
  ``servo_timeout``  s without a servo target before the stream counts as stopped (0.1)
  ``scene``          sim: workcell obstacles file (MJCF or YAML), optional
  ``trajectory_action``  name of the FollowJointTrajectory action (default
                     ``~follow_joint_trajectory``; e.g. ``/jaka_zu5_controller/follow_joint_trajectory``)

Topics: ``~tool_position``, ``~joint_position``, ``~robot_states`` and ``joint_states``, all
from one publisher thread that nothing blocks; blocking moves wait in their service threads.
"""
from __future__ import annotations

import logging
import sys
import threading
import time
import warnings

import rospy
from geometry_msgs.msg import TwistStamped
from sensor_msgs.msg import JointState

from jaka_msgs.msg import RobotMsg

from ..driver import RobotDriver
from ..models import MODEL_NAMES, load_model
from ..robot_state import RobotState
from . import messages
from .diagnostics import Diagnostics
from .frames_tf import FrameBroadcaster
from .services import advertise, advertise_faults
from .snapshot_service import advertise_snapshot
from .trajectory_action import TrajectoryActionServer


def make_backend(kind: str, model_name: str, params: dict):
    """The backend named by ``~backend``; imported lazily so the twin's MuJoCo is not loaded
    for a real controller and vice versa."""
    model = load_model(model_name)
    if kind == "sim":
        from ..sim.backend import SimBackend
        return SimBackend(model, scene=params.get("scene") or None)
    if kind == "controller":
        from ..controller.backend import ControllerBackend
        return ControllerBackend(model, host=params["ip"], command_port=params["command_port"],
                                 status_port=params["status_port"])
    raise ValueError(f"unknown backend {kind!r}; expected 'sim' or 'controller'")


# Periods without a new sample after which the latest is published again (the source is
# stuck); shorter stalls are caught up sample by sample when the source resumes.
STALL_PERIODS = 5


def _direct_publisher(name: str, msg_type) -> rospy.Publisher:
    """A publisher that writes each message to its subscribers' sockets in the publishing
    thread (rospy's ``queue_size=None``). With a queue, rospy hands every message to one
    thread per subscriber and wakes it (a ``Condition.notify`` and a thread switch per
    message and subscriber: the node's largest cost at 4 topics × 125 Hz); the publisher
    thread here does nothing else. A socket's send buffer holds seconds of these small
    messages, so a subscriber that falls behind for a while does not hold the thread up; one
    that is alive but stops reading altogether would, once its buffer is full (a subscriber
    that goes away is dropped by rospy)."""
    with warnings.catch_warnings():
        # rospy warns about queue_size=None for the sake of callers in callbacks
        warnings.simplefilter("ignore")
        return rospy.Publisher(name, msg_type, queue_size=None)


class StatePublisher:
    """Publishes the state at ``rate`` Hz from its own thread.

    When the backend has a sample clock at that rate (the twin's 8 ms cycle at 125 Hz), each
    sample is published the moment it exists: no phase between the physics and the publisher
    to add to the sample's age or to a servo target's round trip. Every cycle gets its
    message, also those the physics caught up on after a stall or that came while this thread
    waited for the CPU (each with its own stamp). If no sample comes for STALL_PERIODS periods
    (the source is stuck) the latest one is published again, so the topics stay alive.
    Otherwise it runs on its own clock: deadlines are absolute (``next += period``) so
    the rate does not drift with the time the publishing takes; after a stall it
    resynchronises instead of bursting.
    """

    def __init__(self, driver: RobotDriver, rate: float):
        self._driver = driver
        self._period = 1.0 / rate
        self._msgs = messages.StateMessages(driver.model.joint_names)
        self._tool = _direct_publisher("~tool_position", TwistStamped)
        self._joints = _direct_publisher("~joint_position", JointState)
        self._states = _direct_publisher("~robot_states", RobotMsg)
        self._joint_states = _direct_publisher("joint_states", JointState)
        self._count = 0
        self._window = (time.monotonic(), 0)
        self._rate = 0.0
        self._thread = threading.Thread(target=self._run, name="state-publisher", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _publish_once(self, st: RobotState | None = None) -> None:
        """Publish ``st`` (default: the latest sample) on every topic."""
        st = self._driver.state() if st is None else st
        msgs = self._msgs
        msgs.fill(st)
        self._tool.publish(msgs.tool)
        self._joints.publish(msgs.joints)
        self._states.publish(msgs.robot)
        self._joint_states.publish(msgs.joints)
        self._count += 1

    def measured_rate(self) -> float:
        """Messages per second per topic since the previous call (diagnostics, 1 Hz)."""
        t0, n0 = self._window
        now = time.monotonic()
        if now - t0 > 0.5:
            self._rate = (self._count - n0) / (now - t0)
            self._window = (now, self._count)
        return self._rate

    @property
    def follows_samples(self) -> bool:
        """True when publishing follows the backend's sample clock (see the class)."""
        period = self._driver.sample_period
        return period is not None and abs(period / self._period - 1.0) < 0.01

    def _publish_safely(self, st: RobotState | None = None) -> None:
        """:meth:`_publish_once`, logging instead of raising."""
        try:
            self._publish_once(st)
        except Exception as exc:  # noqa: BLE001 — a bad sample must not stop the stream
            rospy.logerr_throttle(5.0, f"state publishing failed: {exc!r}")

    def _run(self) -> None:
        if self.follows_samples:
            self._run_on_samples()
        else:
            self._run_on_clock()

    def _run_on_samples(self) -> None:
        last = self._driver.state().stamp - 1e-6     # from the current sample on
        while not rospy.is_shutdown():
            if not self._driver.wait_for_sample(last, STALL_PERIODS * self._period):
                self._publish_safely()          # stuck source: the latest again
                continue
            for st in self._driver.states_since(last):
                self._publish_safely(st)
                last = st.stamp                 # also past a sample that failed

    def _run_on_clock(self) -> None:
        deadline = time.monotonic()
        while not rospy.is_shutdown():
            self._publish_safely()
            deadline += self._period
            delay = deadline - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            elif delay < -self._period:
                deadline = time.monotonic()


class _ToRosout(logging.Handler):
    """The backends log with ``logging`` (they know nothing of ROS); show it where ROS users
    look: rosout and the console."""

    def emit(self, record: logging.LogRecord) -> None:
        message = self.format(record)
        if record.levelno >= logging.ERROR:
            rospy.logerr(message)
        elif record.levelno >= logging.WARNING:
            rospy.logwarn(message)
        else:
            rospy.loginfo(message)


def _forward_logging() -> None:
    logger = logging.getLogger("jaka_driver")
    logger.setLevel(logging.INFO)
    logger.addHandler(_ToRosout())
    logger.propagate = False


def _params() -> dict:
    return {
        "backend": rospy.get_param("~backend", "sim"),
        "model": str(rospy.get_param("~model", "zu5")).lower(),
        "rate": float(rospy.get_param("~rate", 125.0)),
        "ip": rospy.get_param("~ip", rospy.get_param("ip", "10.5.5.100")),
        "command_port": int(rospy.get_param("~command_port", 10001)),
        "status_port": int(rospy.get_param("~status_port", 10000)),
        "jog_timeout": float(rospy.get_param("~jog_timeout", 3.0)),
        "servo_timeout": float(rospy.get_param("~servo_timeout", 0.1)),
        "scene": rospy.get_param("~scene", ""),
    }


def main() -> int:
    rospy.init_node("jaka_driver")
    _forward_logging()
    p = _params()
    if p["model"] not in MODEL_NAMES:
        rospy.logfatal(f"unknown model {p['model']!r}; expected one of {', '.join(MODEL_NAMES)}")
        return 2
    if not 1.0 <= p["rate"] <= 1000.0:
        rospy.logfatal(f"~rate {p['rate']} Hz is outside 1–1000 Hz")
        return 2
    try:
        backend = make_backend(p["backend"], p["model"], p)
    except ValueError as exc:
        rospy.logfatal(str(exc))
        return 2
    driver = RobotDriver(backend, jog_timeout=p["jog_timeout"], servo_timeout=p["servo_timeout"])
    driver.start()
    rospy.on_shutdown(driver.shutdown)
    publisher = StatePublisher(driver, p["rate"])
    publisher.start()
    advertise(driver)
    advertise_faults(backend)
    advertise_snapshot(backend)
    TrajectoryActionServer(driver, rospy.get_param("~trajectory_action",
                                                   "~follow_joint_trajectory"))
    FrameBroadcaster(driver)
    Diagnostics(driver, publisher.measured_rate)
    rospy.loginfo(f"jaka_driver ready: backend {p['backend']}, model {p['model']}, "
                  f"{p['rate']:g} Hz")
    rospy.spin()
    return 0


if __name__ == "__main__":
    sys.exit(main())
