"""The state topics: ``~tool_position``, ``~joint_position``, ``~robot_states`` and
``joint_states`` (and ``/clock`` in sim time), every sample of the backend published once, the
moment it exists, from one thread that nothing blocks (:class:`StatePublisher`); each sample is
offered to ``~io_states`` too (:mod:`.io_states`: on change and at 10 Hz)."""
from __future__ import annotations

import threading
import warnings
from contextlib import contextmanager

import rospy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState

from jaka_msgs.msg import RobotMsg

from ..backend.robot_state import RobotState
from ..driver import RobotDriver
from ..host import realtime
from . import messages
from .io_states import IoStatesTopic

DEFAULT_RATE_HZ = 125.0     # the controller's cycle

# Periods without a new sample after which the latest is published again (the source is
# stuck); shorter stalls are caught up sample by sample when the source resumes.
STALL_PERIODS = 5


@contextmanager
def _synchronous_publishers():
    """Context in which ``rospy.Publisher(..., queue_size=None)`` is made without rospy's
    warning (given for the sake of callers in callbacks): such a publisher writes each
    message to its subscribers' sockets in the publishing thread. With a queue, rospy hands
    every message to one thread per subscriber and wakes it (a ``Condition.notify`` and a
    thread switch per message and subscriber: the node's largest cost at 4 topics × 125 Hz);
    the publisher thread here does nothing else. A socket's send buffer holds seconds of
    these small messages, so a subscriber that falls behind for a while does not hold the
    thread up; one that is alive but stops reading altogether would, once its buffer is full
    (a subscriber that goes away is dropped by rospy)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


class StatePublisher:
    """Publishes each new sample of the backend once, the moment it exists, from its own thread.

    The thread sleeps on the backend's samples (:meth:`Backend.wait_for_sample`: the twin's
    8 ms cycles, a controller's status packets) — no timer of its own, so no phase between the
    source and the publisher to add to a sample's age, and no sample published twice or not at
    all. Every sample gets its message, also those the twin caught up on after a stall or that
    came while this thread waited for the CPU (each with its own stamp). ``rate`` (Hz) is the
    highest rate: a sample less than half a period after the last one's due time waits for
    the next, due times advancing by whole periods, so a lower ``rate`` keeps its average.
    If no sample comes for STALL_PERIODS periods (the source is stuck, or a controller link is
    down) the latest state is published again, so the topics stay alive and say so. In sim time
    every sample is published, whatever ``rate`` says, and a stall is time standing still.
    """

    def __init__(self, driver: RobotDriver, rate: float):
        self._driver = driver
        self._clock = driver.clock
        self._period = 1.0 / rate
        self._msgs = messages.StateMessages(driver.model.joint_names, driver.conventions)
        with _synchronous_publishers():     # tool_position's type is the conventions'
            self._tool = rospy.Publisher("~tool_position", type(self._msgs.tool),
                                         queue_size=None)
            self._joints = rospy.Publisher("~joint_position", JointState, queue_size=None)
            self._states = rospy.Publisher("~robot_states", RobotMsg, queue_size=None)
            self._joint_states = rospy.Publisher("joint_states", JointState, queue_size=None)
        self._io = IoStatesTopic(self._clock)
        # The twin owns time: /clock gets every cycle's time, just before that cycle's
        # sample, and the twin waits for this thread rather than outrun it.
        self._sim_clock = None
        if self._clock.simulated:             # every sample, whatever ~rate says
            self._sim_clock = rospy.Publisher("/clock", Clock, queue_size=100)
            self._clock.add_consumer()
        #: per-sample publishers of other modules (the wrench topics), called after the state
        #: topics with the same sample, in this thread
        self.also_publish: list = []
        self._count = 0
        self._window = (self._clock.now(), 0)
        self._rate = 0.0
        self._thread = threading.Thread(target=self._run, name="state-publisher", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _publish_once(self, st: RobotState | None = None) -> None:
        """Publish ``st`` (default: the latest sample) on every topic."""
        st = self._driver.state() if st is None else st
        msgs = self._msgs
        msgs.fill(st)
        if self._sim_clock is not None:
            self._sim_clock.publish(msgs.clock)
        self._tool.publish(msgs.tool)
        self._joints.publish(msgs.joints)
        self._states.publish(msgs.robot)
        self._joint_states.publish(msgs.joints)
        self._io.offer(st)
        for publish in self.also_publish:
            publish(st)
        self._count += 1

    def measured_rate(self) -> float:
        """Messages per second (of the driver's clock) per topic since the previous call
        (diagnostics, 1 Hz)."""
        t0, n0 = self._window
        now = self._clock.now()
        if now - t0 > 0.5:
            self._rate = (self._count - n0) / (now - t0)
            self._window = (now, self._count)
        return self._rate

    def _publish_safely(self, st: RobotState | None = None) -> None:
        """:meth:`_publish_once`, logging instead of raising."""
        try:
            self._publish_once(st)
        except Exception as exc:  # noqa: BLE001 — a bad sample must not stop the stream
            rospy.logerr_throttle(5.0, f"state publishing failed: {exc!r}")

    @realtime.runs_periodically
    def _run(self) -> None:
        every_sample = self._sim_clock is not None
        last = self._driver.state().stamp - 1e-6     # from the current sample on
        due = None                                   # stamp from which the next one is due
        while not rospy.is_shutdown():
            if not self._driver.wait_for_sample(last, STALL_PERIODS * self._period):
                if not every_sample:
                    self._publish_safely()      # stuck source: the latest again
                continue                        # (in sim time, time merely stands still)
            for st in self._driver.states_since(last):
                last = st.stamp                 # also past a sample that failed
                if not every_sample:
                    if due is not None and st.stamp < due - 0.5 * self._period:
                        continue                # ~rate is lower than the samples' rate
                    # whole periods from the last due time, unless that fell behind
                    due = st.stamp + self._period if due is None or st.stamp > due + \
                        self._period else due + self._period
                self._publish_safely(st)
                if every_sample:
                    self._clock.consumed(last)
