"""The tool connector through ROS on the zu5 twin (one node for the module): JAKA's twelve TIO
functions as services, each set answering its read-back, each get what was set, every refusal
naming field, value and limit and changing nothing, and ~tool_io_state showing it all (the
twin has no device on its connector here: signals are kept, their values stay 0)."""
import pytest

from support.ros_harness import Recorder, wait_until
from jaka_driver_msgs.msg import RS485Comm, ToolIOState
from jaka_driver_msgs.srv import (AddToolSignal, DeleteToolSignal, GetRS485Comm, GetRS485Mode,
                                  GetToolPinMode, GetToolPower, GetToolSignals, SendRS485Frame,
                                  SetRS485Comm, SetRS485Mode, SetToolPinMode, SetToolPower)

pytestmark = pytest.mark.ros

COMM = dict(slave_id=1, baudrate=115200, databit=8, stopbit=1, parity=78)


@pytest.fixture(scope="module")
def state(sim_driver, rospy_node):
    return Recorder(sim_driver.name("tool_io_state"), ToolIOState)


def test_jakas_demo_set_up_reads_back_and_shows_on_the_state_topic(call, state):
    r = call("set_tio_vout_param", SetToolPower, enable=True, voltage=24.0)
    assert (r.ret, r.enable, r.voltage) == (1, True, 24.0), r.message
    assert call("get_tio_vout_param", GetToolPower).voltage == 24.0
    assert call("set_tio_pin_mode", SetToolPinMode, pin_type=2, mode=1).mode == 1
    assert call("get_tio_pin_mode", GetToolPinMode, pin_type=2).mode == 1
    assert call("set_rs485_chn_mode", SetRS485Mode, channel=1, mode=0).ret == 1
    assert call("get_rs485_chn_mode", GetRS485Mode, channel=1).mode == 0
    r = call("set_rs485_chn_comm", SetRS485Comm, channel=1, comm=RS485Comm(**COMM))
    assert r.ret == 1 and r.comm.baudrate == 115200
    assert call("get_rs485_chn_comm", GetRS485Comm, channel=1).comm.slave_id == 1
    r = call("send_tio_rs_command", SendRS485Frame, channel=1, frame=[1, 6, 1, 0, 0, 1])
    assert r.ret == 1 and "01 06 01 00 00 01" in r.message
    r = call("add_tio_rs_signal", AddToolSignal, name="grip_pos", channel=1, sig_type=3,
             address=0x202, frequency=10)
    assert r.ret == 1 and [s.name for s in r.signals] == ["grip_pos"]
    assert [s.address for s in call("get_rs485_signal_info", GetToolSignals).signals] == [0x202]
    msg = wait_until(lambda: (m := state.latest()) and m.signals and m, 2.0)
    assert msg and msg.present and msg.power_on and msg.voltage == 24.0
    assert (msg.ai_pin_mode, list(msg.channel_modes), msg.channel_comm[1].baudrate) == \
        (1, [0, 0], 115200)
    assert len(msg.tool_di) == 2 and msg.signals[0].frequency == 10
    r = call("del_tio_rs_signal", DeleteToolSignal, name="grip_pos")
    assert r.ret == 1 and list(r.signals) == []


@pytest.mark.parametrize("leaf, srv_type, fields, says", [
    ("set_tio_vout_param", SetToolPower, dict(enable=True, voltage=5.0),
     "voltage is 5.0 V, expected 24 or 12 V"),
    ("set_tio_pin_mode", SetToolPinMode, dict(pin_type=3, mode=0), "pin_type is 3"),
    ("get_tio_pin_mode", GetToolPinMode, dict(pin_type=3), "pin_type is 3"),
    ("set_rs485_chn_mode", SetRS485Mode, dict(channel=2, mode=0),
     "channel is 2, expected one of 0, 1 (0 = RS485H, 1 = RS485L)"),
    ("get_rs485_chn_comm", GetRS485Comm, dict(channel=2), "channel is 2"),
    ("set_rs485_chn_comm", SetRS485Comm, dict(channel=1, comm=RS485Comm(**{**COMM,
                                                                         "baudrate": 250000})),
     "baudrate is 250000, expected 4800–230400"),
    ("add_tio_rs_signal", AddToolSignal, dict(name="x", channel=1, sig_type=3, address=1,
                                              frequency=20), "frequency is 20 Hz, expected 1–10"),
    ("add_tio_rs_signal", AddToolSignal, dict(name="a" * 20, channel=1, sig_type=3, address=1,
                                              frequency=5), "expected at most 19"),
    ("del_tio_rs_signal", DeleteToolSignal, dict(name="nothing"), "'nothing' is no signal"),
    ("send_tio_rs_command", SendRS485Frame, dict(channel=0, frame=[1, 3, 2, 1, 0, 1]),
     "the DO pins' mode is 0x00, expected 0xff"),
])
def test_a_refusal_names_field_value_and_limit(call, leaf, srv_type, fields, says):
    before = call("get_rs485_chn_comm", GetRS485Comm, channel=1).comm
    r = call(leaf, srv_type, **fields)
    assert r.ret in (-2, -9) and says in r.message, r.message
    assert call("get_rs485_chn_comm", GetRS485Comm, channel=1).comm == before
