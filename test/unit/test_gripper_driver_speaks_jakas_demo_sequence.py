"""The gripper driver above the tool connector (devices/gripper.py) makes JAKA's demo sequence
of the tool connector's calls — 24 V, the AI pins to RS485L, channel 1 Modbus RTU, 115200 8N1
for slave 1, then a TIO signal per status register at 10 Hz — sends DH's frames as JAKA's
demos write them (``01 06 01 03 01 F4`` goes to 500 ‰), reads its state from the signals'
values, and passes a refusal of the connector on unchanged, stopping there."""
from jaka_driver.common.results import Code, Result
from jaka_driver.devices import DH_FIGURES, DH_PGI, ConnectorSetup, GripState, ModbusGripper


class RecordingToolIo:
    """Records each call; ``refuse`` names a call answered -9; ``values`` the signals'."""

    def __init__(self, refuse: str = "", values: dict | None = None):
        self.calls, self.refuse, self.values, self.rows = [], refuse, values or {}, []

    def __getattr__(self, name):
        def call(*args):
            self.calls.append((name, *args))
            if name == "add_signal":
                self.rows.append({"name": args[0], "value": self.values.get(args[0])})
            if name == self.refuse:
                return Result.failure(Code.WRONG_MODE, f"{name} refused")
            return Result.success("ok")
        return call

    def signals(self):
        return list(self.rows)


def test_set_up_is_jakas_demo_sequence_and_three_signals():
    io = RecordingToolIo()
    assert ModbusGripper(io, DH_PGI, DH_FIGURES).set_up().ok
    assert io.calls == [("set_power", True, 24.0), ("set_pin_mode", 2, 1),
                        ("set_channel_mode", 1, 0), ("set_channel_comm", 1, 1, 115200, 8, 1, 0),
                        ("add_signal", "gripper_init_state", 1, 3, 0x0200, 10),
                        ("add_signal", "gripper_grip_state", 1, 3, 0x0201, 10),
                        ("add_signal", "gripper_position", 1, 3, 0x0202, 10)]


def test_channel_0_puts_the_do_pins_in_rs485_mode():
    io = RecordingToolIo()
    ModbusGripper(io, DH_PGI, DH_FIGURES, ConnectorSetup(channel=0, volts=12.0)).set_up()
    assert io.calls[:3] == [("set_power", True, 12.0), ("set_pin_mode", 1, 1),
                            ("set_channel_mode", 0, 0)]


def test_a_refusal_of_the_connector_is_answered_and_ends_the_set_up():
    io = RecordingToolIo(refuse="set_channel_mode")
    result = ModbusGripper(io, DH_PGI, DH_FIGURES).set_up()
    assert result.code == -9 and "set_channel_mode refused" in result.message
    assert [c[0] for c in io.calls] == ["set_power", "set_pin_mode", "set_channel_mode"]


def test_frames_are_jakas_demo_frames_or_carry_their_crc():
    io = RecordingToolIo()
    gripper = ModbusGripper(io, DH_PGI, DH_FIGURES)
    gripper.initialise()
    gripper.move_to(0.0475)                       # half the 95 mm stroke: 500 ‰
    gripper.initialise(full=True)
    assert [c[1:] for c in io.calls] == [(1, bytes.fromhex("010601000001")),
                                         (1, bytes.fromhex("0106010301F4")),
                                         (1, bytes.fromhex("0106010000A5"))]
    io8 = RecordingToolIo()
    ModbusGripper(io8, DH_PGI, DH_FIGURES, ConnectorSetup(crc=True)).initialise()
    assert io8.calls == [("send", 1, bytes.fromhex("01060100000149F6"))]


def test_the_state_comes_from_the_signals_values():
    io = RecordingToolIo(values={"gripper_init_state": 1, "gripper_grip_state": 2,
                                 "gripper_position": 600})
    gripper = ModbusGripper(io, DH_PGI, DH_FIGURES)
    gripper.set_up()
    state = gripper.state()
    assert state.initialised and state.grip_state == GripState.CAUGHT and state.object_held
    assert state.position == 600 and abs(state.opening - 0.057) < 1e-12
    assert gripper.powered


def test_an_effort_in_newtons_becomes_the_nearest_force_setting():
    assert [DH_FIGURES.percent(n) for n in (0.0, 45.0, 100.0, 160.0, 500.0)] == \
        [20, 20, 58, 100, 100]
    assert DH_FIGURES.force(58) == 45.0 + 115.0 * 38 / 80
