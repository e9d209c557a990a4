"""The controller path of the gripper: the emulator with the DH gripper mounted by its one option
(``gripper="dh_pgi"``, the command line's ``--gripper dh_pgi``) over config/scenes/pick.yaml,
reached only through JAKA's TIO commands.

- JAKA's demo sequence, sent as JAKA's SDK writes it (the requests below are its literal bytes,
  docs/protocol.md "Tool connector"): 24 V, the AI pins to RS485L, channel 1 Modbus RTU at
  115200 8N1 for slave 1, then DH's frames initialise (seen done on a TIO signal on 0x0200)
  and go to 500 ‰ — the twin's fingers open, then stop at half the stroke; an 8-byte frame
  with a wrong CRC moves nothing, one carrying its right CRC closes them.
- The driver on the controller backend does the twin's pick (test_twin_gripper_picks_a_part)
  with the same ``driver.gripper`` calls and the same results: the close on the box ends with
  grip state 2 at the box's 57 mm, the box stays within 2 mm of the grasp through the lift and
  the carry, opening ends with grip state 1 and leaves the box on the table 300 mm further; an
  empty close reaches its opening with grip state 1.

The emulator's twin runs on the wall clock: every wait is a bounded poll of what the twin or the
status packets report; the box's drift is recorded in the twin's own cycles.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.controller import ControllerBackend
from jaka_driver.devices.modbus_frames import write_register
from jaka_driver.devices.register_maps import DH_PGI, GripState
from jaka_driver.driver import RobotDriver
from jaka_driver.emulator import Emulator
from support.emulated_arm import LINK_TIMEOUTS
from support.jaka_sdk_model import RC_OK, JakaSdk
from support.jaka_sdk_tio import JakaSdkTio
from support.part_watch import PartWatch, move_by
from support.ros_harness import wait_until

SCENE = str(Path(__file__).resolve().parents[2] / "config" / "scenes" / "pick.yaml")
TABLE_TOP, BOX_HALF = 0.20, 0.03                  # m (the scene's)
GRASP_Z = 0.125                                   # m below the flange: the grasp point
STROKE = 0.095                                    # m
POSITION = DH_PGI.writes["position"]
#: JAKA's demo sequence as its SDK sends it (compact JSON, sorted keys)
DEMO = [
    ("set_tio_vout_param", (1, 0),
     '{"cmdName":"set_tio_vout_param","tio_vout_ena":1,"tio_vout_vol":0}'),
    ("set_tio_pin_mode", (2, 1), '{"cmdName":"set_tio_pin_mode","pinMode":1,"pinType":2}'),
    ("set_rs485_chn_mode", (1, 0), '{"chnId":1,"chnMode":0,"cmdName":"set_rs485_chn_mode"}'),
    ("set_rs485_chn_comm", (1, 1, 115200, 8, 1, 78),
     '{"baudrate":115200,"chn_id":1,"cmdName":"set_rs485_chn_comm","databit":8,"parity":78,'
     '"slaveId":1,"stopbit":1}'),
    ("send_tio_rs_command", (1, (1, 6, 1, 0, 0, 1)),
     '{"chn_id":1,"cmdBuf":[1,6,1,0,0,1],"cmdName":"send_tio_rs_command"}'),
]
DH_500 = '{"chn_id":1,"cmdBuf":[1,6,1,3,1,244],"cmdName":"send_tio_rs_command"}'


@pytest.fixture(scope="module")
def emu():
    with Emulator("zu5", command_port=0, status_port=0, scene=SCENE, gripper="dh_pgi",
                  programs=None) as emulator:
        yield emulator


def opening(emu) -> float:
    """The twin's fingers' opening (m), between two of its cycles."""
    with emu.backend._physics.lock:
        return emu.backend.tool_device.opening()


def settles_at(emu, target: float, timeout: float = 2.0) -> bool:
    """The fingers come to rest within 1 mm of ``target`` m within ``timeout`` s (two looks
    40 ms apart, 5 of the twin's cycles)."""
    def still_there():
        first = opening(emu)
        time.sleep(0.04)
        last = opening(emu)
        return abs(first - target) < 0.001 and abs(last - target) < 0.001 and \
            abs(last - first) < 1e-4
    return bool(wait_until(still_there, timeout))


def initialised(tio) -> bool:
    rc, rows = tio.get_rs485_signal_info()
    return rc == RC_OK and rows == [("init", 1, 3, 0x0200, 1, 10)]


def test_jakas_demo_sequence_moves_the_twins_fingers_with_6_and_8_byte_frames(emu):
    sdk = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    tio = JakaSdkTio(sdk)
    try:
        for function, args, literal in DEMO:
            assert getattr(tio, function)(*args) == RC_OK, function
            assert sdk.sent[-1] == literal
        # JAKA's demos wait for the initialisation; a client sees it on a TIO signal
        assert tio.add_tio_rs_signal("init", 1, 3, 0x0200, 10) == RC_OK
        assert wait_until(lambda: initialised(tio), 3.0)
        assert settles_at(emu, STROKE)                      # initialised: open
        assert tio.send_tio_rs_command(1, [1, 6, 1, 3, 1, 0xF4]) == RC_OK
        assert sdk.sent[-1] == DH_500
        assert settles_at(emu, STROKE / 2)                  # 500 ‰
        close = write_register(1, POSITION, 0, crc=True)    # 8 bytes with the CRC
        bad = bytearray(write_register(1, POSITION, 1000, crc=True))
        bad[-2] ^= 0xFF
        assert len(close) == len(bad) == 8
        assert tio.send_tio_rs_command(1, list(bad)) == RC_OK     # sent; the gripper ignores it
        assert not settles_at(emu, STROKE, 0.3) and settles_at(emu, STROKE / 2, 0.1)
        assert tio.send_tio_rs_command(1, list(close)) == RC_OK
        assert settles_at(emu, 0.0)                         # closed on nothing
    finally:
        sdk.close()


@pytest.fixture(scope="module")
def driver(emu):
    backend = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                                **LINK_TIMEOUTS)
    driver = RobotDriver(backend, gripper="dh_pgi")
    driver.start()
    yield driver
    driver.shutdown()


def grip_state_after(driver, wanted: GripState, near: float | None = None,
                     timeout: float = 3.0):
    """The door's state once its polled grip state is ``wanted`` (and its opening within 1 mm
    of ``near`` m: the state before the command may be ``wanted`` too), or the last one seen."""
    def there():
        state = driver.gripper.state()
        return state.grip_state == wanted and (
            near is None or abs(state.opening - near) < 0.001) and state
    return wait_until(there, timeout) or driver.gripper.state()


def test_the_driver_on_the_controller_backend_picks_the_box_as_on_the_twin(emu, driver):
    gripper = driver.gripper
    assert gripper.set_up().ok, "the controller's connector set up for the gripper"
    assert gripper.powered
    assert gripper.initialise().ok
    assert wait_until(lambda: gripper.state().initialised, 3.0)
    assert grip_state_after(driver, GripState.REACHED, STROKE).position == 1000
    watch = PartWatch(emu.backend, "gripper_grasp", locked=True)
    move_by(driver, dz=-(0.4431 - GRASP_Z - (TABLE_TOP + BOX_HALF)) * 1000, speed=400.0)
    assert gripper.move(0.0, 100.0).ok
    state = grip_state_after(driver, GripState.CAUGHT)
    assert state.grip_state == GripState.CAUGHT and state.object_held
    assert 0.056 <= state.opening <= 0.0575                  # the box's 57 mm
    grasped = watch.offset()
    assert np.linalg.norm(grasped) < 0.002
    watch.on = True
    move_by(driver, dz=150.0, speed=250.0)
    move_by(driver, dy=300.0, speed=250.0)
    watch.on = False
    drift = np.linalg.norm(np.array(watch.offsets) - grasped, axis=1)
    assert len(drift) > 100 and drift.max() < 0.002, f"the box moved {drift.max() * 1000:.2f} mm"
    assert gripper.state().grip_state == GripState.CAUGHT
    move_by(driver, dz=-145.0, speed=400.0)                  # 5 mm above the table
    assert gripper.move(STROKE).ok
    assert grip_state_after(driver, GripState.REACHED, STROKE).grip_state == GripState.REACHED
    resting = watch.position()
    assert resting[2] == pytest.approx(TABLE_TOP + BOX_HALF, abs=0.001)
    assert resting[1] == pytest.approx(0.114 + 0.3, abs=0.003)
    move_by(driver, dz=70.0, speed=400.0)                    # the pads clear of the box
    assert gripper.move(0.02).ok                             # an empty close: 20 mm
    state = grip_state_after(driver, GripState.REACHED, 0.02)
    assert state.grip_state == GripState.REACHED and not state.object_held
    assert state.opening == pytest.approx(0.02, abs=0.001)
