"""The gripper driver above the tool connector (devices/gripper.py) on the twin's real connector
(sim/tool_connector.py's SimToolIO on the real IO board, its cycles called by hand) makes JAKA's
demo sequence — 24 V, the AI pins to RS485L, channel 1 Modbus RTU, 115200 8N1 for slave 1, then
a TIO signal per status register at 10 Hz — sends DH's frames as JAKA's demos write them
(``01 06 01 03 01 F4`` goes to 500 ‰), reads its state from the signals' values, is
"powered" only while the connector's supply is on, and passes a refusal of the connector on
unchanged, stopping there."""
import threading

from jaka_driver.backend.tool_io import ChannelComm, PinType, Signal
from jaka_driver.common.models import load_model
from jaka_driver.devices import DH_FIGURES, DH_PGI, ConnectorSetup, GripState, ModbusGripper
from jaka_driver.sim.io_board import IoBoard
from jaka_driver.sim.tool_connector import SimToolIO
from support.fake_tool_device import FakeToolDevice


class Registers(FakeToolDevice):
    """A device on the connector that records the frames it hears and answers ``values`` while
    powered, as a Modbus slave answers its holding registers."""

    def __init__(self, values=None):
        super().__init__()
        self.values = dict(values or {})

    def read_register(self, channel, sig_type, address):
        return self.values.get(address) if self.volts else None


def connector(device=None) -> SimToolIO:
    io = SimToolIO(IoBoard(load_model("zu5").io_sizes), threading.RLock())
    io.attach(device or Registers())
    return io


def cycles(io: SimToolIO, n: int) -> None:
    for _ in range(n):
        io.on_cycle()


def test_set_up_is_jakas_demo_sequence_and_three_signals():
    io = connector()
    assert ModbusGripper(io, DH_PGI, DH_FIGURES).set_up().ok
    s = io.settings()
    assert (s.power_on, s.voltage_code, s.volts) == (True, 0, 24.0)
    assert s.pin_modes[PinType.AI] == 1 and s.channel_modes[1] == 0
    assert s.comm[1] == ChannelComm(1, 115200, 8, 1, 78)
    assert io.signals() == (Signal("gripper_init_state", 1, 3, 0x0200, 0, 10),
                            Signal("gripper_grip_state", 1, 3, 0x0201, 0, 10),
                            Signal("gripper_position", 1, 3, 0x0202, 0, 10))


def test_a_second_set_up_keeps_the_signals_and_channel_0_puts_the_do_pins_in_rs485_mode():
    io = connector()
    gripper = ModbusGripper(io, DH_PGI, DH_FIGURES, ConnectorSetup(channel=0, volts=12.0))
    assert gripper.set_up().ok and gripper.set_up().ok
    s = io.settings()
    assert (s.power_on, s.volts, s.pin_modes[PinType.DO], s.channel_modes[0]) == \
        (True, 12.0, 0xFF, 0)
    assert [(x.name, x.channel) for x in io.signals()] == [
        ("gripper_init_state", 0), ("gripper_grip_state", 0), ("gripper_position", 0)]
    assert gripper.take_down().ok and io.signals() == ()


def test_a_refusal_of_the_connector_is_answered_and_ends_the_set_up():
    io = connector()
    result = ModbusGripper(io, DH_PGI, DH_FIGURES, ConnectorSetup(baudrate=1200)).set_up()
    assert result.code == -2 and "baudrate is 1200, expected 4800–230400" in result.message
    assert io.settings().comm[1].baudrate == 115200 and io.signals() == ()
    assert ModbusGripper(io, DH_PGI, DH_FIGURES, ConnectorSetup(volts=5.0)).set_up().code == -2


def test_frames_are_jakas_demo_frames_or_carry_their_crc():
    device = Registers()
    io = connector(device)
    gripper = ModbusGripper(io, DH_PGI, DH_FIGURES)
    assert gripper.initialise().code == -9          # the AI pins are not RS485L yet
    assert device.frames == []
    gripper.set_up()
    gripper.initialise()
    gripper.move_to(0.0475)                       # half the 95 mm stroke: 500 ‰
    gripper.initialise(full=True)
    assert device.frames == [(1, bytes.fromhex("010601000001"), 115200),
                             (1, bytes.fromhex("0106010301F4"), 115200),
                             (1, bytes.fromhex("0106010000A5"), 115200)]
    device8 = Registers()
    io8 = connector(device8)
    gripper8 = ModbusGripper(io8, DH_PGI, DH_FIGURES, ConnectorSetup(crc=True))
    gripper8.set_up()
    gripper8.initialise()
    assert device8.frames == [(1, bytes.fromhex("01060100000149F6"), 115200)]


def test_the_state_comes_from_the_signals_polled_values_while_the_supply_is_on():
    device = Registers({0x0200: 1, 0x0201: 2, 0x0202: 600})
    io = connector(device)
    gripper = ModbusGripper(io, DH_PGI, DH_FIGURES)
    assert not gripper.powered and gripper.state().grip_state is None
    gripper.set_up()
    assert gripper.powered and not gripper.state().initialised    # nothing polled yet
    cycles(io, 1)                                                 # the first poll
    state = gripper.state()
    assert state.initialised and state.grip_state == GripState.CAUGHT and state.object_held
    assert state.position == 600 and abs(state.opening - 0.057) < 1e-12
    assert io.set_power(0, 0).ok
    cycles(io, 13)              # a poll the unpowered gripper does not answer: values kept
    assert io.signals()[0].value == 1
    assert not gripper.powered and not gripper.state().initialised


def test_an_effort_in_newtons_becomes_the_nearest_force_setting():
    assert [DH_FIGURES.percent(n) for n in (0.0, 45.0, 100.0, 160.0, 500.0)] == \
        [20, 20, 58, 100, 100]
    assert DH_FIGURES.force(58) == 45.0 + 115.0 * 38 / 80
