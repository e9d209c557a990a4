"""JAKA's SDK (test/jaka_sdk_model.py: its requests and its strict reading, from the measured
evidence of sdk_wire_formats §5 and §7) drives the sensor and force control of an emulated arm
that carries one (``Emulator(force_sensor=True)``, ``--force-sensor``), unmodified, over the
table of config/scenes/table.yaml:

- the sensor on and off, zeroing, get_torque_sensor_data for the three types, and the status
  packet's torqsensor as the SDK parses it (all three wrenches, status, the sensor's payload);
- the sensor's tool payload set and read back within the SDK's own 1 s wait;
- admittance config, compliance type, frames, tool drive config, filter, soft limit round-trip
  as the SDK reads them; velocity levels and the compliance condition accepted;
- constant force presses the table with 10 N, disable_force_control ends it; tool drive follows
  a hand on the tool; identification through start / staus / result finds 2 kg at 50 mm;
- what a controller refuses (force control with the sensor off, zeroing while it presses) is
  rc 2, the SDK's "function call failed".

Times are the emulator's wall clock (its twin runs in real time); the waits are bounded polls.
"""
from __future__ import annotations

import time

import numpy as np
import pytest

from support.jaka_sdk_model import RC_FAILED, RC_OK, JakaSdk
from support.ros_harness import wait_until

from jaka_driver.common.models import repo_root
from jaka_driver.emulator import Emulator
from jaka_driver.kinematics import Kinematics

TABLE = str(repo_root() / "config" / "scenes" / "table.yaml")
G = 9.81
#: joints (rad) from home: the flange 65 mm higher, the tool still down (the probe clear of the
#: table), and from there the end pose of an identification that turns the tool three ways
#: (the tip never lower than 65 mm above the table)
UP = np.array([0.0, -0.2, 0.4, -0.2, 0.0, 0.0])
TURNED = np.array([0.0, 0.0, 0.0, 0.9, -0.9, 1.5])


@pytest.fixture(scope="module")
def emu():
    with Emulator("zu5", command_port=0, status_port=0, start="enabled", force_sensor=True,
                  scene=TABLE) as emulator:
        yield emulator


@pytest.fixture(scope="module")
def sdk(emu):
    handle = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    yield handle
    handle.close()


@pytest.fixture
def sensor_on(sdk):
    """The sensor on (the packet shows it), every force control off afterwards."""
    assert sdk.set_torque_sensor_mode(1) == RC_OK
    assert wait_until(lambda: sdk.get_robot_status()[1].torq_sensor.status == 1, 1.0)
    yield sdk
    assert sdk.disable_force_control() == RC_OK


def mean_data(sdk, kind, seconds=0.2):
    """get_torque_sensor_data(kind)'s data averaged over ``seconds`` (noise 0.05 N a sample)."""
    values, end = [], time.monotonic() + seconds
    while time.monotonic() < end or not values:
        rc, (status, errcode, data) = sdk.get_torque_sensor_data(kind)
        assert rc == RC_OK and status == 1 and errcode == 0
        values.append(data)
        time.sleep(0.01)
    return np.mean(values, axis=0)


def test_the_sdk_reads_the_three_wrenches_by_type_and_in_the_status_packet(emu, sensor_on):
    sdk = sensor_on
    assert sdk.set_payload(0.0, [0.0, 0.0, 0.0]) == RC_OK
    assert sdk.set_torq_sensor_tool_payload(0.0, [0.0, 0.0, 0.0]) == RC_OK
    time.sleep(0.1)
    assert sdk.zero_end_sensor() == RC_OK                  # zeroed without the payload
    assert sdk.set_payload(2.0, [0.0, 0.0, 50.0]) == RC_OK
    time.sleep(0.3)
    # at home the tool points down: 2 kg reads Fz +19.62 N in the sensor frame, no moment
    rotation = Kinematics(emu.model).flange_pose(emu.backend.state().joint_position)[:3, :3]
    weight = 2.0 * rotation.T @ np.array([0.0, 0.0, -G])
    expected = np.concatenate([weight, np.cross([0.0, 0.0, 0.05], weight)])
    actual, general = (mean_data(sdk, kind) for kind in (1, 2))   # JAKA's 1 actual, 2 general
    print(f"actual {np.round(actual, 3)}, general {np.round(general, 3)}, expected "
          f"{np.round(expected, 3)}")
    assert np.linalg.norm(actual[:3] - expected[:3]) <= 0.02 * 2.0 * G
    # general is the raw reading: the offset zeroing took out (the configured bias) is in it
    bias = emu.model.force_sensor.bias
    assert np.linalg.norm(general - actual - bias) < 0.1
    ts = sdk.get_robot_status()[1].torq_sensor
    assert ts.real_torque == ts.act_torque           # one sample: no tool payload on the sensor
    assert sdk.set_torq_sensor_tool_payload(2.0, [0.0, 0.0, 50.0]) == RC_OK   # SDK's 1 s wait
    assert sdk.get_torq_sensor_tool_payload() == (RC_OK, (2.0, [0.0, 0.0, 50.0]))
    time.sleep(0.05)
    assert np.linalg.norm(mean_data(sdk, 3)[:3]) <= 0.02 * 2.0 * G    # real: the weight gone
    rc, st = sdk.get_robot_status()
    ts = st.torq_sensor
    assert rc == RC_OK and ts.status == 1 and ts.errcode == 0
    assert (ts.payload_mass, ts.payload_centroid) == (2.0, [0.0, 0.0, 50.0])
    assert np.linalg.norm(np.array(ts.act_torque[:3]) - expected[:3]) <= 0.02 * 2.0 * G
    assert np.linalg.norm(ts.real_torque[:3]) <= 0.02 * 2.0 * G
    assert np.linalg.norm(np.array(ts.torque) - general) < 1.0     # raw, one sample's noise
    assert sdk.set_torque_sensor_mode(0) == RC_OK
    assert wait_until(lambda: sdk.get_robot_status()[1].torq_sensor.status == 0, 1.0)
    assert sdk.get_torque_sensor_data(1) == (RC_OK, (0, 0, [0.0] * 6))
    assert sdk.set_payload(0.0, [0.0, 0.0, 0.0]) == RC_OK
    assert sdk.set_torq_sensor_tool_payload(0.0, [0.0, 0.0, 0.0]) == RC_OK


def test_settings_round_trip_as_the_sdk_reads_them(sensor_on):
    sdk = sensor_on
    assert sdk.set_admit_ctrl_config(2, 1, 50.0, 10.0, 0, 0.25) == RC_OK
    rc, rows = sdk.get_admit_ctrl_config()
    assert rc == RC_OK and rows[2] == (1, 50.0, 0.25, 10.0, 0)
    assert all(row[0] == 0 for axis, row in enumerate(rows) if axis != 2)
    assert sdk.set_compliant_type(1, 1) == RC_OK and sdk.get_compliant_type() == (RC_OK, (1, 1))
    assert sdk.set_ft_ctrl_frame(1) == RC_OK and sdk.get_ft_ctrl_frame() == (RC_OK, 1)
    assert sdk.set_ft_ctrl_frame(0) == RC_OK and sdk.get_ft_ctrl_frame() == (RC_OK, 0)
    assert sdk.set_tool_drive_config(0, 1, 30.0, 0.5) == RC_OK
    rc, drive = sdk.get_tool_drive_config()
    assert rc == RC_OK and drive[0] == (0, 1, 30.0, 0.5) and drive[1] == (1, 0, 0.0, 0.0)
    assert sdk.set_tool_drive_frame(1) == RC_OK and sdk.get_tool_drive_frame() == (RC_OK, 1)
    assert sdk.set_tool_drive_frame(0) == RC_OK
    assert sdk.set_torque_sensor_filter(10.0) == RC_OK
    assert sdk.get_torque_sensor_filter() == (RC_OK, 10.0)
    assert sdk.set_torque_sensor_filter(0.0) == RC_OK
    assert sdk.set_torque_sensor_soft_limit([100, 100, 150, 10, 10, 8]) == RC_OK
    assert sdk.get_torque_sensor_soft_limit() == (RC_OK, [100.0, 100.0, 150.0, 10.0, 10.0, 8.0])
    assert sdk.set_vel_compliant_ctrl(2, [0.8, 0.5, 0.2, 0.0]) == RC_OK
    assert sdk.set_compliance_condition([0.0, 0.0, 30.0, 0.0, 0.0, 0.0]) == RC_OK
    # what a controller checks: an axis beyond 5, a rate order the SDK's VelCom forbids
    assert sdk.set_admit_ctrl_config(6, 1, 50.0, 0.0, 0, 0.0) != RC_OK
    assert sdk.set_vel_compliant_ctrl(2, [0.2, 0.5, 0.8, 0.0]) != RC_OK
    assert sdk.set_tool_drive_config(0, 0, 0.0, 0.0) == RC_OK
    assert sdk.set_compliance_condition([0.0] * 6) == RC_OK


def test_constant_force_presses_the_table_with_10_n_and_disable_ends_it(emu, sensor_on):
    sdk = sensor_on
    assert sdk.zero_end_sensor() == RC_OK
    assert sdk.set_admit_ctrl_config(2, 1, 40.0, 10.0, 0, 0.0) == RC_OK
    assert sdk.set_compliant_type(1, 1) == RC_OK
    assert sdk.enable_admittance_ctrl(1) == RC_OK
    assert sdk.get_tool_drive_state() == (RC_OK, (1, 0))
    # zeroing while force control presses is refused, as on the twin
    assert sdk.zero_end_sensor() == RC_FAILED
    time.sleep(2.5)                      # the twin settles within 2 s (its own test)
    fz = mean_data(sdk, 1, 0.3)[2]
    print(f"constant force through the SDK: Fz {fz:.2f} N")
    assert abs(fz + 10.0) <= 0.5         # the sensor reads the table pushing back
    assert sdk.disable_force_control() == RC_OK
    assert sdk.get_tool_drive_state() == (RC_OK, (0, 0))
    assert sdk.set_admit_ctrl_config(2, 0, 40.0, 0.0, 0, 0.0) == RC_OK
    assert sdk.set_compliant_type(1, 0) == RC_OK
    # back up off the table for the next test
    assert sdk.joint_move(list(emu.model.home), 0, 0.5, 1.0) == RC_OK and sdk.wait_inpos(10.0)


def test_tool_drive_follows_a_hand_on_the_tool(emu, sensor_on):
    sdk = sensor_on
    assert sdk.zero_end_sensor() == RC_OK
    for axis in (0, 1, 2):
        assert sdk.set_tool_drive_config(axis, 1, 40.0, 0.0) == RC_OK
    assert sdk.enable_tool_drive(1) == RC_OK
    p0 = emu.backend.state().tcp_pose[:3, 3].copy()
    assert emu.backend.twin.push_tool(np.array([20.0, 0, 0, 0, 0, 0]), 0.5).ok   # the hand
    time.sleep(1.0)
    moved = (emu.backend.state().tcp_pose[:3, 3] - p0) * 1000.0
    print(f"tool drive through the SDK: moved {np.round(moved, 1)} mm along the push")
    assert moved[0] > 10.0 and np.linalg.norm(moved[1:]) < 0.1 * moved[0]
    assert sdk.enable_tool_drive(0) == RC_OK
    assert sdk.get_tool_drive_state() == (RC_OK, (0, 0))
    for axis in (0, 1, 2):
        assert sdk.set_tool_drive_config(axis, 0, 40.0, 0.0) == RC_OK
    assert sdk.joint_move(list(emu.model.home), 0, 0.5, 1.0) == RC_OK and sdk.wait_inpos(10.0)


def test_identification_through_start_status_and_result_finds_2_kg_at_50_mm(emu, sensor_on):
    sdk = sensor_on
    assert sdk.set_payload(2.0, [0.0, 0.0, 50.0]) == RC_OK
    up = emu.model.home + UP
    assert sdk.joint_move(up.tolist(), 0, 0.5, 1.0) == RC_OK and sdk.wait_inpos(10.0)
    assert sdk.start_torq_sensor_payload_identify((up + TURNED).tolist()) == RC_OK
    statuses = []

    def done():
        rc, status = sdk.get_torq_sensor_identify_staus()
        statuses.append(status)
        return rc == RC_OK and status != 1

    assert wait_until(done, 20.0, period=0.1)
    rc, (mass, centroid) = sdk.get_torq_sensor_payload_identify_result()
    print(f"identified through the SDK: {mass:.4f} kg at {np.round(centroid, 2)} mm "
          f"({len(statuses)} polls)")
    assert 1 in statuses and statuses[-1] == 0
    assert rc == RC_OK and abs(mass - 2.0) <= 0.04
    assert np.linalg.norm(np.array(centroid) - [0.0, 0.0, 50.0]) <= 2.0
    assert sdk.set_payload(0.0, [0.0, 0.0, 0.0]) == RC_OK
    assert sdk.joint_move(list(emu.model.home), 0, 0.5, 1.0) == RC_OK and sdk.wait_inpos(10.0)


def test_force_control_with_the_sensor_off_is_refused(sdk):
    assert sdk.set_torque_sensor_mode(0) == RC_OK
    assert wait_until(lambda: sdk.get_robot_status()[1].torq_sensor.status == 0, 1.0)
    assert sdk.set_admit_ctrl_config(2, 1, 40.0, 10.0, 0, 0.0) == RC_OK
    assert sdk.enable_admittance_ctrl(1) == RC_FAILED
    assert sdk.zero_end_sensor() == RC_FAILED
    assert sdk.get_tool_drive_state() == (RC_OK, (0, 0))
    assert sdk.set_admit_ctrl_config(2, 0, 40.0, 0.0, 0, 0.0) == RC_OK
