"""``~tool_io_state`` (``jaka_driver_msgs/ToolIOState``, latched): the tool connector — its
supply, pin modes, channel modes and comm, the tool's DI/DO/AI and every signal with its latest
value — published whenever any of it changes: offered each sample by the state publisher's
thread (the tool's pins and the signals change with the samples), and after each tool-connector
service (a setting changes between two samples, or while a twin's simulated time is paused).
Through ``driver.tool_io`` only.
"""
from __future__ import annotations

import threading

import rospy

from jaka_driver_msgs.msg import RS485Comm, ToolIOState, ToolSignal

from ..backend.robot_state import RobotState
from ..backend.tool_io import VOLTAGES, ChannelComm, Signal, ToolIOSettings
from ..driver import RobotDriver

TOOL = 1                                   # IO type of the tool's pins


def comm_message(c: ChannelComm) -> RS485Comm:
    return RS485Comm(slave_id=c.slave_id, baudrate=c.baudrate, databit=c.databit,
                     stopbit=c.stopbit, parity=c.parity)


def signal_message(s: Signal) -> ToolSignal:
    return ToolSignal(name=s.name, channel=s.channel, sig_type=s.sig_type, address=s.address,
                      value=int(s.value), frequency=s.frequency)


def state_message(present: bool, s: ToolIOSettings, signals, io, stamp: float) -> ToolIOState:
    msg = ToolIOState(present=present, power_on=s.power_on,
                      voltage=VOLTAGES[s.voltage_code], di_pin_mode=s.pin_modes[0],
                      do_pin_mode=s.pin_modes[1], ai_pin_mode=s.pin_modes[2],
                      channel_modes=bytes(int(m) for m in s.channel_modes),
                      channel_comm=[comm_message(c) for c in s.comm],
                      tool_di=list(io.get(("digital", TOOL, 0), ())),
                      tool_do=list(io.get(("digital", TOOL, 1), ())),
                      tool_ai=list(io.get(("analog", TOOL, 0), ())),
                      signals=[signal_message(x) for x in signals])
    msg.header.stamp = rospy.Time.from_sec(stamp)
    return msg


class ToolIOTopic:
    """``~tool_io_state``: :meth:`offer` each sample, :meth:`refresh` after a request."""

    def __init__(self, driver: RobotDriver):
        self._driver = driver
        self._pub = rospy.Publisher("~tool_io_state", ToolIOState, queue_size=10, latch=True)
        self._lock = threading.Lock()
        self._last = None

    def offer(self, st: RobotState) -> None:
        result = self._driver.tool_io.state()
        if not result.ok:
            return
        present, settings, signals = result.value
        io = st.io
        key = (present, settings, signals, tuple(io.get(k, ()) for k in
                                        (("digital", TOOL, 0), ("digital", TOOL, 1),
                                         ("analog", TOOL, 0))))
        with self._lock:
            if key == self._last:
                return
            self._last = key
            self._pub.publish(state_message(present, settings, signals, io, st.stamp))

    def refresh(self) -> None:
        self.offer(self._driver.state())
