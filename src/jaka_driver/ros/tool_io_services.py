"""The tool connector on ROS (docs/interface.md, "Tool connector"): JAKA's twelve TIO
functions as services named as JAKA's SDK names them, request message → ``driver.tool_io``
(RobotDriver's door, :mod:`jaka_driver.driver.tool_io_requests`) → response, on every backend
(a backend without a connector answers -9). Each set answers the setting as read back; every
refusal names the field, the value and the limit. The state topic: :mod:`.tool_io_topics`.
"""
from __future__ import annotations

import rospy

from jaka_driver_msgs import srv as msgs

from ..backend.tool_io import VOLTAGES, ChannelComm
from ..common.results import Result
from ..driver import RobotDriver
from .tool_io_topics import ToolIOTopic, comm_message, signal_message


def advertise_tool_io(driver: RobotDriver, also_publish: list) -> list:
    """Every tool-connector service and ``~tool_io_state`` (offered each sample through the
    state publisher's ``also_publish``)."""
    t = driver.tool_io
    topic = ToolIOTopic(driver)
    also_publish.append(topic.offer)

    def service(name, srv_type, call, fill=None):
        response_type = srv_type._response_class

        def serve(req):
            result: Result = call(req)
            if not result.ok:
                rospy.logwarn("%s refused (%d): %s", name, result.code, result.message)
            topic.refresh()
            response = response_type(ret=int(result.code), message=result.message)
            if result.ok and fill is not None:
                fill(response, result.value, req)
            return response
        return rospy.Service(f"~{name}", srv_type, serve)

    def power(response, value, _req):
        on, code = value
        response.enable, response.voltage = bool(on), VOLTAGES[code]

    def mode(response, value, _req):
        response.mode = int(value)

    def signals(response, value, _req):
        response.signals = [signal_message(s) for s in value]

    return [
        service("set_tio_vout_param", msgs.SetToolPower,
                lambda r: t.set_power(r.enable, r.voltage), power),
        service("get_tio_vout_param", msgs.GetToolPower, lambda r: t.power(), power),
        service("set_tio_pin_mode", msgs.SetToolPinMode,
                lambda r: t.set_pin_mode(r.pin_type, r.mode), mode),
        service("get_tio_pin_mode", msgs.GetToolPinMode, lambda r: t.pin_mode(r.pin_type), mode),
        service("set_rs485_chn_mode", msgs.SetRS485Mode,
                lambda r: t.set_channel_mode(r.channel, r.mode), mode),
        service("get_rs485_chn_mode", msgs.GetRS485Mode, lambda r: t.channel_mode(r.channel),
                mode),
        service("set_rs485_chn_comm", msgs.SetRS485Comm,
                lambda r: t.set_channel_comm(r.channel, ChannelComm(
                    r.comm.slave_id, r.comm.baudrate, r.comm.databit, r.comm.stopbit,
                    r.comm.parity)),
                lambda response, c, _r: setattr(response, "comm", comm_message(c))),
        service("get_rs485_chn_comm", msgs.GetRS485Comm, lambda r: t.channel_comm(r.channel),
                lambda response, c, _r: setattr(response, "comm", comm_message(c))),
        service("send_tio_rs_command", msgs.SendRS485Frame,
                lambda r: t.send_frame(r.channel, bytes(r.frame))),
        service("add_tio_rs_signal", msgs.AddToolSignal,
                lambda r: t.add_signal(r.name, r.channel, r.sig_type, r.address, r.frequency),
                signals),
        service("del_tio_rs_signal", msgs.DeleteToolSignal, lambda r: t.delete_signal(r.name),
                signals),
        service("get_rs485_signal_info", msgs.GetToolSignals, lambda r: t.signals(), signals),
    ]

