"""The twin's grippers really hold parts (docs/twin.md, "Grippers and parts"), on the twin: a Zu 5
with its flange force/torque sensor, the DH gripper after it and config/scenes/pick.yaml (a
0.3 kg box 57 mm wide, 60 % of the 95 mm opening, on a table), in simulated time as fast as
the machine steps, the gripper driven only by Modbus frames.

- The sensor zeroed with the gripper open and empty; the close on the box ends with grip
  state 2 (caught) before the commanded position; lifted 150 mm and carried 300 mm at
  250 mm/s, the box stays within 2 mm of where it sat in the grasp, every cycle, and the sensor
  reads its weight, 0.3 × 9.81 = 2.94 N, within 3 %; opened, the box falls onto the table and
  stays there.
- A close with nothing between the fingers reaches the commanded opening, grip state 1.
- The suction cup, switched by tool DO 0, lifts the same box; its vacuum reads on tool DI 0;
  closing the valve puts it down; the twin's reset puts the box back where the scene placed
  it.

Everything goes through the twin's real tool connector (``backend.tool_io``, SimToolIO): frames
sent on its channel 1 reach the DhGripper, the gripper door's state is the connector's signals
polled at 10 Hz in the twin's cycles, the suction cup's valve is tool DO 0 on the IO board.
Positions are read from MuJoCo's data between cycles (the twin's own test)."""
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.devices.modbus_frames import write_register
from jaka_driver.devices.register_maps import DH_PGI, GripState
from jaka_driver.driver import RobotDriver
from jaka_driver.sim import SimBackend
from support.part_watch import PartWatch, move_by

MODEL = load_model("zu5")
SCENE = str(Path(__file__).resolve().parents[2] / "config" / "scenes" / "pick.yaml")
BOX_MASS, BOX_HALF, TABLE_TOP = 0.3, 0.03, 0.20          # kg, m (the scene's)
GRASP_Z = 0.125                   # m below the flange: the DH gripper's grasp point
SUCTION_Z = 0.09                  # m below the flange: the suction cup's face
INIT, FORCE, POSITION = (DH_PGI.writes[k] for k in ("init", "force", "position"))
GRIP_STATE, OPENING = DH_PGI.reads["grip_state"], DH_PGI.reads["position"]
CHANNEL = 1                       # RS485L, as JAKA's demos wire a DH gripper


class ToolLine:
    """The test's hand on the tool connector: frames on the gripper's channel, a register read
    as the connector's poll makes it, the supply, and tool DOs through the driver."""

    def __init__(self, backend: SimBackend, driver: RobotDriver):
        self.io = backend.tool_io
        self.device = backend.tool_device
        self.driver = driver

    def set_power(self, volts: float):
        assert self.io.set_power(int(volts > 0), 0 if volts in (0.0, 24.0) else 1).ok

    def send(self, frame: bytes):
        result = self.io.send_frame(CHANNEL, frame)
        assert result.ok, result.message

    def read(self, address: int):
        return self.device.read_register(CHANNEL, 3, address)

    def set_output(self, index: int, level: float):
        assert self.driver.set_io("digital", 1, index, level).ok       # IO type 1: the tool


def twin_with(tool: str, site: str, door: str):
    """A started driver on the zu5 twin with ``tool`` mounted on its tool connector, its
    gripper door ``door``; the tool line and a watch on the box in ``site``'s frame."""
    backend = SimBackend(MODEL, scene=SCENE, sim_time=True, real_time_factor=0,
                         force_sensor=True, gripper=tool)
    watch = PartWatch(backend, site)
    driver = RobotDriver(backend, gripper=door)
    line = ToolLine(backend, driver)
    driver.start()
    try:
        yield driver, line, watch
    finally:
        driver.shutdown()


@pytest.fixture(scope="module")
def dh():
    yield from twin_with("dh_pgi", "gripper_grasp", "dh_pgi")


@pytest.fixture
def gripper(dh):
    """The DH twin fresh at home, the tool connector set up for it by ``driver.gripper`` (24 V,
    the AI pins RS485L, channel 1 Modbus RTU, three signals), initialised (open), time held."""
    driver, tool, watch = dh
    assert driver.twin.reset().ok
    with driver.clock.hold():
        assert driver.gripper.set_up().ok
        assert driver.gripper.initialise().ok
        driver.clock.sleep(1.0)
        assert driver.gripper.state().initialised
        yield driver, tool, watch
        watch.on = False


def mean_force(driver, seconds=0.25) -> np.ndarray:
    """The sensor's force (N, sensor frame) averaged over ``seconds`` of samples."""
    samples, last = [], driver.state().stamp
    while len(samples) < round(seconds / 0.008):
        driver.clock.sleep(0.04)
        for st in driver.states_since(last):
            samples.append(st.force.actual[:3])
            last = st.stamp
    return np.mean(samples, axis=0)


def test_the_dh_gripper_catches_lifts_carries_and_drops_the_box_with_its_weight_on_the_sensor(
        gripper):
    driver, tool, watch = gripper
    assert driver.force.sensor_enable(True).ok
    driver.clock.sleep(0.1)
    assert driver.force.zero_sensor().ok                 # the gripper open and empty
    move_by(driver, dz=-(0.4431 - GRASP_Z - (TABLE_TOP + BOX_HALF)) * 1000)
    assert driver.gripper.move(0.0, 100.0).ok            # close on it, 100 N per jaw
    driver.clock.sleep(0.8)
    state = driver.gripper.state()                       # the signals, polled at 10 Hz
    assert state.grip_state == GripState.CAUGHT and state.object_held
    assert 0.056 <= state.opening <= 0.0575              # the box's 57 mm, pads pressed in
    grasped = watch.offset()
    assert np.linalg.norm(grasped) < 0.002               # the grasp point is the box's centre
    watch.on = True
    move_by(driver, dz=150.0, speed=250.0)
    driver.clock.sleep(0.3)
    weight = np.linalg.norm(mean_force(driver))
    assert weight == pytest.approx(BOX_MASS * 9.81, rel=0.03)
    move_by(driver, dy=300.0, speed=250.0)
    drift = np.linalg.norm(np.array(watch.offsets) - grasped, axis=1)
    assert len(drift) > 100 and drift.max() < 0.002, f"the box moved {drift.max() * 1000:.2f} mm"
    assert tool.read(GRIP_STATE) == GripState.CAUGHT
    watch.on = False
    driver.clock.sleep(0.3)
    assert np.linalg.norm(mean_force(driver)) == pytest.approx(BOX_MASS * 9.81, rel=0.03)
    move_by(driver, dz=-145.0)                            # 5 mm above the table
    assert driver.gripper.move(0.095).ok
    driver.clock.sleep(1.0)
    assert driver.gripper.state().grip_state == GripState.REACHED
    resting = watch.position()
    assert resting[2] == pytest.approx(TABLE_TOP + BOX_HALF, abs=0.001)   # on the table
    assert resting[1] == pytest.approx(0.114 + 0.3, abs=0.003)            # 300 mm further
    driver.clock.sleep(0.5)
    assert np.linalg.norm(watch.position() - resting) < 0.0005 and watch.speed() < 0.001
    assert np.linalg.norm(mean_force(driver)) < 0.15                    # empty again


def test_an_empty_close_reaches_the_commanded_opening_with_grip_state_1(gripper):
    driver, tool, _ = gripper
    tool.send(write_register(1, POSITION, 300, crc=True))   # 8 bytes, with the CRC
    driver.clock.sleep(0.2)
    assert tool.read(GRIP_STATE) == GripState.MOVING
    driver.clock.sleep(0.8)
    assert tool.read(GRIP_STATE) == GripState.REACHED
    assert tool.read(OPENING) == pytest.approx(300, abs=11)   # within 1 mm of 28.5 mm
    assert driver.gripper.move(0.02).ok                       # through the door: 20 mm
    driver.clock.sleep(0.5)
    state = driver.gripper.state()
    assert state.grip_state == GripState.REACHED and not state.object_held
    assert state.opening == pytest.approx(0.02, abs=0.001)


def test_the_gripper_ignores_frames_until_initialised_and_everything_unpowered(dh):
    driver, tool, _ = dh
    assert driver.twin.reset().ok
    with driver.clock.hold():
        assert driver.gripper.set_up().ok
        tool.set_power(0.0)
        tool.send(write_register(1, INIT, 1))
        assert tool.read(GRIP_STATE) is None                 # unpowered: no answer
        driver.clock.sleep(0.2)
        refused = driver.gripper.move(0.05)                  # the door: not powered
        assert refused.code == -9 and "not powered" in refused.message
        tool.set_power(24.0)
        tool.send(write_register(1, POSITION, 1000))         # not initialised: no move
        driver.clock.sleep(0.5)
        assert tool.read(DH_PGI.reads["init_state"]) == 0 and tool.read(OPENING) == 0
        refused = driver.gripper.move(0.05)
        assert refused.code == -9 and "not initialised" in refused.message
        for request, field in ((lambda: driver.gripper.move(0.1), "position 0.1 m"),
                               (lambda: driver.gripper.set_force(10), "force 10 %"),
                               (lambda: driver.gripper.set_speed(101), "speed 101 %")):
            result = request()
            assert result.code == -2 and field in result.message, result.message
        bad = bytearray(write_register(1, INIT, 1, crc=True))
        bad[-1] ^= 0xFF
        tool.send(bytes(bad))                                # a wrong CRC: ignored
        driver.clock.sleep(0.5)
        assert tool.read(DH_PGI.reads["init_state"]) == 0 and tool.read(OPENING) == 0
        tool.send(write_register(1, INIT, 0xA5))             # full calibration, 6 bytes
        driver.clock.sleep(1.0)
        assert tool.read(DH_PGI.reads["init_state"]) == 1 and tool.read(OPENING) == 1000


@pytest.fixture(scope="module")
def cup():
    yield from twin_with("suction", "suction_grasp", "none")


def test_the_suction_cup_switched_by_tool_do_0_lifts_the_box_and_puts_it_down(cup):
    driver, tool, watch = cup
    assert driver.twin.reset().ok
    with driver.clock.hold():
        tool.set_power(24.0)
        # the cup's face 1 mm into the box's top
        move_by(driver, dz=-(0.4431 - SUCTION_Z - (TABLE_TOP + 2 * BOX_HALF) + 0.001) * 1000)
        assert tool.device.tool_inputs() == {0: 0.0}
        tool.set_output(0, 1.0)
        driver.clock.sleep(0.1)
        assert tool.device.tool_inputs() == {0: 1.0}         # vacuum
        held = watch.offset()
        watch.on = True
        move_by(driver, dz=150.0, speed=250.0)
        move_by(driver, dy=300.0, speed=250.0)
        drift = np.linalg.norm(np.array(watch.offsets) - held, axis=1)
        assert drift.max() < 0.002, f"the box moved {drift.max() * 1000:.2f} mm"
        assert watch.position()[2] > TABLE_TOP + BOX_HALF + 0.14     # lifted
        move_by(driver, dz=-148.0)
        tool.set_output(0, 0.0)
        driver.clock.sleep(0.5)
        assert tool.device.tool_inputs() == {0: 0.0}
        assert watch.position()[2] == pytest.approx(TABLE_TOP + BOX_HALF, abs=0.001)
        assert watch.position()[1] == pytest.approx(0.114 + 0.3, abs=0.003)
    assert driver.twin.parts()["box"][1, 3] == pytest.approx(0.414, abs=0.003)
    assert driver.twin.reset().ok                             # ~sim/reset: the box back
    assert np.allclose(driver.twin.parts()["box"][:3, 3], [0.482, 0.114, 0.23], atol=1e-9)
