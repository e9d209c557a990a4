"""The emulator talks JAKA's TCP protocol to a client that uses no project code: plain sockets
and ``json``, the way a third-party JAKA client would (docs/protocol.md)."""
from __future__ import annotations

import json
import socket
import threading
import time

import numpy as np
import pytest

from support.emulated_arm import emulator
from support.raw_client import RawClient
from support.threads import run_all


HOME_DEG = [0.0, 90.0, -90.0, 90.0, 90.0, 0.0]
REQUIRED_STATUS_FIELDS = (
    "len", "joint_actual_position", "actual_position", "task_state", "enabled", "powered_on",
    "inpos", "emergency_stop", "protective_stop", "errcode", "errmsg", "current_tool_id",
    "current_user_id", "din", "dout", "ain", "aout", "tio_din", "tio_dout", "drag_status")


def read_status(port: int, seconds: float) -> list[tuple[dict, int]]:
    """(packet, its byte length) for every packet received in ``seconds``."""
    data = b""
    with socket.create_connection(("127.0.0.1", port), timeout=2.0) as sock:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            sock.settimeout(max(0.01, end - time.monotonic()))
            try:
                data += sock.recv(65536)
            except socket.timeout:
                break
    decoder = json.JSONDecoder()
    text = data.decode()
    packets, i = [], text.find('{"len":')
    while i >= 0:
        try:
            obj, end = decoder.raw_decode(text, i)
        except ValueError:
            break   # the last packet was cut by the end of the read
        packets.append((obj, len(text[i:end].encode())))
        i = end
    return packets


# the recorded Zu 5s (fw 1.5.14: its version, its 30 ms, its recorded answers), found powered
# on and enabled
EMULATOR = dict(profile="zu5s-1.5.14", start="enabled")


@pytest.fixture
def client(emu):
    c = RawClient(emu.command_port)
    yield c
    c.close()


def test_queries_answer_in_wire_units(client):
    version = client.call("get_version")
    assert (version["cmdName"], version["errorCode"]) == ("get_version", "0")
    # a real-looking version (clients parse it); the emulator says what it is in robot_name
    assert version["version"] == "1.5.14_13_X64" and "emulator" in version["robot_name"]
    assert version["errorMsg"] == ""
    state = client.call("get_robot_state")
    assert (state["power"], state["enable"]) == ("powered_on", "robot_enabled")
    joints = client.call("get_joint_pos")["joint_pos"]
    np.testing.assert_allclose(joints, HOME_DEG, atol=0.05)   # degrees, not radians
    tcp = client.call("get_tcp_pos")["tcp_pos"]
    assert len(tcp) == 6 and 50 < np.linalg.norm(tcp[:3]) < 2000   # millimetres
    # what fw 1.5.14 answered in every recorded run
    assert client.call("emergency_stop_status") == {"errorCode": "1",
                                                    "errorMsg": "Exception:function call failed"}
    assert client.call("protective_stop_status")["protective_stop"] == 0
    assert client.call("is_in_servomove")["in_servomove"] == 0
    data = client.call("get_data")
    assert set(REQUIRED_STATUS_FIELDS) <= set(data)


def test_unknown_command_gets_an_error_and_the_connection_stays(client):
    reply = client.call("fly_to_the_moon", speed=3)
    assert reply["cmdName"] == "fly_to_the_moon"
    assert reply["errorCode"] != "0"
    assert "unknown command" in reply["errorMsg"]
    assert client.call("get_version")["errorCode"] == "0"


def test_malformed_json_gets_an_error_reply(client):
    client.send(b'{"cmdName": "get_version",,}')
    assert client.read()["errorCode"] != "0"
    client.send(b"hello")
    reply = client.read()
    assert reply["errorCode"] != "0" and "not a JSON object" in reply["errorMsg"]
    client.send(b'{"speed": 3}')
    assert "cmdName" in client.read()["errorMsg"]
    client.send(b'{"cmdName": "get_ver')          # and then nothing: discarded after 1 s
    t0 = time.monotonic()
    reply = client.read(timeout=3.0)
    assert reply["errorCode"] != "0" and "incomplete" in reply["errorMsg"]
    assert 0.9 < time.monotonic() - t0 < 2.0
    assert client.call("get_version")["errorCode"] == "0"


def test_split_and_merged_requests(client):
    request = json.dumps({"cmdName": "get_joint_pos"}).encode()
    for piece in (request[:5], request[5:11], request[11:]):
        client.send(piece)
        time.sleep(0.02)
    assert client.read()["cmdName"] == "get_joint_pos"
    client.send(json.dumps({"cmdName": "get_version"}).encode()
                + json.dumps({"cmdName": "drag_status"}).encode())
    assert [client.read()["cmdName"], client.read()["cmdName"]] == ["get_version", "drag_status"]


def test_several_clients_at_once(emu):
    errors = []

    def work(k):
        c = RawClient(emu.command_port)
        try:
            for _ in range(25):
                reply = c.call("get_joint_pos")
                if reply["errorCode"] != "0" or len(reply["joint_pos"]) != 6:
                    errors.append((k, reply))
        except Exception as exc:  # noqa: BLE001
            errors.append((k, exc))
        finally:
            c.close()

    run_all([threading.Thread(target=work, args=(k,), name=f"client {k}") for k in range(5)], 10.0)
    assert not errors


def test_status_stream_at_the_profiles_period_with_the_fields(emu):
    assert emu.period == 0.030       # the recorded Zu 5s: about 30 ms per packet
    packets = read_status(emu.status_port, 1.0)
    # Wall clock: the status push is wall-paced as a controller's; a 1 s window of receipts.
    # Never faster than the period (33 a second, one more at each edge of the window). A
    # broadcaster woken later than a whole period resynchronises instead of bursting, so a
    # machine that late costs packets: the lower bound allows it half of them.
    assert 0.5 / emu.period <= len(packets) <= 1 / emu.period + 2, len(packets)
    for packet, size in packets[:5]:
        assert set(REQUIRED_STATUS_FIELDS) <= set(packet)
        assert packet["len"] == size                    # len is the packet's own byte count
        assert len(packet["joint_actual_position"]) == 6
        assert packet["errcode"] == "0x0"
    # array sizes of a real controller's packet
    first = packets[0][0]
    assert len(first["din"]) > 100 and len(first["ain"]) == len(first["aout"]) == 64
    assert len(first["tio_din"]) == len(first["tio_dout"]) == 8


def test_moves_are_acknowledged_at_once_queued_and_inpos_follows_the_queue(emu, client):
    target = HOME_DEG.copy()
    target[0] += 10.0
    reply = client.call("joint_move", jointPosition=target, speed=60.0, accel=300.0, relFlag=0)
    # acknowledged at once: the answer did not wait for the move (0.37 s), which still runs
    assert reply["errorCode"] == "0" and not emu.controller.inpos
    # a second move while the first runs is queued, not refused (as a real controller does)
    queued = client.call("joint_move", jointPosition=HOME_DEG, speed=60.0, accel=300.0,
                         relFlag=0)
    assert queued["errorCode"] == "0"
    state = client.call("get_motion_state")
    assert state["inpos"] is False and state["queue"] == 1 and state["active_queue"] == 2
    flags = [p["inpos"] for p, _ in read_status(emu.status_port, 0.3)]
    assert flags and not any(flags), "inpos false while the queue runs"
    t0 = time.monotonic()
    assert client.call("wait_complete")["errorCode"] == "0"
    assert 0.1 < time.monotonic() - t0 < 5.0, "wait_complete answered when the queue was done"
    state = client.call("get_motion_state")
    assert state["inpos"] is True and state["queue"] == 0
    final = client.call("get_joint_pos")["joint_pos"]
    np.testing.assert_allclose(final, HOME_DEG, atol=np.degrees(1e-3))


def test_motion_is_refused_under_emergency_stop(client):
    assert client.call("emulator_emergency_stop", pressed=1)["errorCode"] == "0"
    try:
        move = client.call("joint_move", jointPosition=HOME_DEG, speed=30.0, accel=100.0,
                           relFlag=0)
        assert move["errorCode"] != "0" and "emergency stop" in move["errorMsg"]
        assert client.call("get_robot_state")["power"] == "powered_off"
        assert client.call("power_on")["errorCode"] != "0"
    finally:
        client.call("emulator_emergency_stop", pressed=0)
    assert client.call("power_on")["errorCode"] == "0"
    assert client.call("enable_robot")["errorCode"] == "0"
    assert client.call("get_robot_state")["enable"] == "robot_enabled"


def test_out_of_range_targets_and_bad_fields_are_refused(client):
    far = HOME_DEG.copy()
    far[2] = 400.0
    reply = client.call("joint_move", jointPosition=far, speed=30.0, accel=100.0, relFlag=0)
    assert reply["errorCode"] != "0" and "joint 3" in reply["errorMsg"]
    reply = client.call("joint_move", jointPosition=[1, 2, 3], speed=30.0, accel=100.0)
    assert reply["errorCode"] != "0" and "jointPosition" in reply["errorMsg"]
    assert client.call("servo_j", jointPosition=HOME_DEG, relFlag=0)["errorCode"] != "0"


def test_servo_mode_round_trip(client):
    assert client.call("servo_move", relFlag=1)["errorCode"] == "0"
    try:
        assert client.call("is_in_servomove")["in_servomove"] == 1
        q = np.array(HOME_DEG)
        for k in range(1, 26):
            q[5] = HOME_DEG[5] + 0.1 * k
            assert client.call("servo_j", jointPosition=q.tolist(), relFlag=0)["errorCode"] == "0"
            time.sleep(0.008)
        too_fast = q.copy()
        too_fast[5] += 10.0   # 10° in 8 ms
        refused = client.call("servo_j", jointPosition=too_fast.tolist(), relFlag=0)
        assert refused["errorCode"] != "0" and "deg/s" in refused["errorMsg"]
        time.sleep(0.2)
        final = client.call("get_joint_pos")["joint_pos"]
        assert abs(final[5] - q[5]) < np.degrees(1e-3)
        # stepNum spreads one set-point over several cycles (4 × 8 ms here)
        q[5] -= 2.5
        reply = client.call("servo_j", jointPosition=q.tolist(), relFlag=0, stepNum=4)
        assert reply["errorCode"] == "0"
        time.sleep(0.25)
        assert abs(client.call("get_joint_pos")["joint_pos"][5] - q[5]) < np.degrees(1e-3)
    finally:
        assert client.call("servo_move", relFlag=0)["errorCode"] == "0"
    assert client.call("is_in_servomove")["in_servomove"] == 0


def test_io_outputs_inputs_and_the_status_stream(emu, client):
    assert client.call("set_digital_output", type=0, index=3, value=1)["errorCode"] == "0"
    assert client.call("set_analog_output", type=0, index=1, value=2.5)["errorCode"] == "0"
    assert client.call("emulator_set_input", signal="digital", type=0, index=2,
                       value=1)["errorCode"] == "0"
    assert client.call("get_digital_input", type=0, index=2)["value"] == 1
    assert client.call("get_analog_output", type=0, index=1)["value"] == 2.5
    packet = read_status(emu.status_port, 0.05)[-1][0]
    # the wire counts IO from 1; the packet's arrays from 0 (the SDK's API index)
    assert packet["dout"][2] == 1 and packet["din"][1] == 1 and packet["aout"][0] == 2.5
    assert client.call("get_digital_input", type=0, index=1)["value"] == 0
    bad = client.call("set_digital_output", type=0, index=999, value=1)
    assert bad["errorCode"] != "0" and "index 999" in bad["errorMsg"]
    zero = client.call("set_digital_output", type=0, index=0, value=1)
    assert zero["errorCode"] != "0" and "index" in zero["errorMsg"]
    client.call("set_digital_output", type=0, index=3, value=0)
    client.call("set_analog_output", type=0, index=1, value=0.0)
    client.call("emulator_set_input", signal="digital", type=0, index=2, value=0)


def test_kinematics_round_trip(client):
    q = [10.0, 80.0, -70.0, 85.0, 95.0, 5.0]
    pose = client.call("kine_forward", jointPosition=q)["cartPosition"]
    back = client.call("kine_inverse", jointPosition=HOME_DEG, cartPosition=pose)
    assert back["errorCode"] == "0"
    np.testing.assert_allclose(back["jointPosition"], q, atol=1e-3)
    unreachable = client.call("kine_inverse", jointPosition=HOME_DEG,
                              cartPosition=[5000, 0, 0, 0, 0, 0])
    assert unreachable["errorCode"] != "0"


def test_quit_closes_only_this_connection(emu, client):
    other = RawClient(emu.command_port)
    try:
        assert client.call("quit")["errorCode"] == "0"
        assert client.closed_by_peer()
        assert other.call("get_version")["errorCode"] == "0"
    finally:
        other.close()


def test_drop_connections_closes_every_client_and_keeps_listening(emu, client):
    status = socket.create_connection(("127.0.0.1", emu.status_port), timeout=2.0)
    other = RawClient(emu.command_port)
    try:
        status.recv(65536)
        assert client.call("emulator_drop_connections")["errorCode"] == "0"
        assert client.closed_by_peer() and other.closed_by_peer()
        status.settimeout(2.0)
        while True:   # drain what was sent before the close
            if not status.recv(65536):
                break
    finally:
        status.close()
        other.close()
    again = RawClient(emu.command_port)
    try:
        assert again.call("get_version")["errorCode"] == "0"
    finally:
        again.close()


def test_io_types_3_to_6_show_in_their_status_arrays():
    """On a controller whose packet carries the relay and fieldbus arrays (the default profile;
    the packet recorded on fw 1.5.14 has none of them)."""
    arrays = {3: "relay_io", 4: "mb_slave_dout", 5: "pn_dev_dout", 6: "eip_adpt_dout"}
    with emulator() as arm, RawClient(arm.command_port) as client:
        for io_type, key in arrays.items():
            assert client.call("set_digital_output", type=io_type, index=2,
                               value=1)["errorCode"] == "0"
        assert client.call("set_analog_output", type=5, index=64, value=1.5)["errorCode"] == "0"
        assert client.call("emulator_set_input", signal="digital", type=4, index=1,
                           value=1)["errorCode"] == "0"
        packet = client.call("get_data")
        for io_type, key in arrays.items():   # 1-based on the wire, 0-based in the arrays
            assert packet[key][1] == 1 and sum(packet[key]) == 1, key
        assert packet["pn_dev_aout"][63] == 1.5 and packet["mb_slave_din"][0] == 1
        assert len(packet["relay_io"]) == 4
        relay_in = client.call("get_digital_input", type=3, index=1)
        assert relay_in["errorCode"] == "1" and "no digital inputs" in relay_in["errorMsg"]
        fifth = client.call("set_digital_output", type=3, index=5, value=1)
        assert fifth["errorCode"] == "1" and "has 4" in fifth["errorMsg"]


def test_servo_filters_are_checked_by_type_and_refused_in_servo_mode(emu, client):
    ok = [{"filter_type": 0}, {"filter_type": 1, "lpf_cf": 0.5},
          {"filter_type": 2, "nlf_max_vr": 90.0, "nlf_max_ar": 500.0, "nlf_max_jr": 5000.0},
          {"filter_type": 3, "mmf_max_buf": 20, "mmf_kp": 0.2, "mmf_kv": 0.1, "mmf_ka": 0.0},
          {"filter_type": 4, "nlf_max_vp": 500.0, "nlf_max_ap": 2000.0, "nlf_max_jp": 9000.0,
           "nlf_max_vr": 90.0, "nlf_max_ar": 500.0, "nlf_max_jr": 5000.0},
          {"filter_type": 5, "mmf_max_buf": 15, "mmf_kp": 0.03}]
    for fields in ok:
        assert client.call("set_servo_move_filter", **fields)["errorCode"] == "0", fields
        assert emu.controller.servo_filter[0] == fields["filter_type"]
    # JAKA's SDK's servo_move_use_joint_LPF(125.0): no controller is known to refuse it; the
    # twin runs what its 8 ms cycle can filter, 62.5 Hz (docs/twin.md, "Servo filters")
    assert client.call("set_servo_move_filter", filter_type=1, lpf_cf=125.0)["errorCode"] == "0"
    assert emu.controller.servo_filter == (1, {"lpf_cf": 125.0})
    assert "cut-off 62.5 Hz" in emu.backend.describe()["servo_filter"]
    for fields, named in (({"filter_type": 1}, "lpf_cf"),
                          ({"filter_type": 1, "lpf_cf": 0}, "lpf_cf"),
                          ({"filter_type": 5, "mmf_max_buf": 1.5, "mmf_kp": 0.1}, "mmf_max_buf"),
                          ({"filter_type": 6}, "filter_type")):
        reply = client.call("set_servo_move_filter", **fields)
        assert reply["errorCode"] == "1" and named in reply["errorMsg"], (fields, reply)
    assert emu.controller.servo_filter == (1, {"lpf_cf": 125.0})      # the refused changed nothing
    assert client.call("servo_move", relFlag=1)["errorCode"] == "0"
    try:
        refused = client.call("set_servo_move_filter", filter_type=0)
        assert refused["errorCode"] == "2" and "servo mode" in refused["errorMsg"]
    finally:
        client.call("servo_move", relFlag=0)
        assert client.call("set_servo_move_filter", filter_type=0)["errorCode"] == "0"


def test_a_filter_sent_in_the_wires_units_shapes_the_twins_servo_stream(emu, client):
    """joint_NLF at 5 deg/s (the wire's unit): a 1° servo_j step (125 deg/s asked) is
    followed, sample by sample of the twin's 8 ms cycles, no faster than that (unfiltered it
    is there in two cycles)."""
    reply = client.call("set_servo_move_filter", filter_type=2, nlf_max_vr=5.0,
                        nlf_max_ar=100.0, nlf_max_jr=2000.0)
    assert reply["errorCode"] == "0"
    assert "0.0872665 rad/s" in emu.backend.describe()["servo_filter"]     # 5 deg/s
    q = client.call("get_joint_pos")["joint_pos"]
    assert client.call("servo_move", relFlag=1)["errorCode"] == "0"
    try:
        since = emu.backend.state().stamp
        target = list(q)
        target[5] += 1.0
        assert client.call("servo_j", jointPosition=target, relFlag=0)["errorCode"] == "0"
        samples = []
        deadline = time.monotonic() + 5.0
        while time.monotonic() < deadline:
            fresh = emu.backend.states_since(since)
            if fresh:
                samples += fresh
                since = fresh[-1].stamp
                if abs(np.degrees(samples[-1].joint_position[5]) - target[5]) < 0.01:
                    break
            time.sleep(0.05)
        stamps = np.array([st.stamp for st in samples])
        j6 = np.degrees([st.joint_position[5] for st in samples])
        assert abs(j6[-1] - target[5]) < 0.01
        step = np.diff(stamps)
        one_cycle = step < 0.012                   # consecutive samples (a reader may lag)
        speed = np.abs(np.diff(j6))[one_cycle] / step[one_cycle]
        assert speed.max() < 5.0 * 1.15            # deg/s: the drives track within 15 %
        assert stamps[-1] - stamps[0] >= 0.2 - 0.008   # 1° at 5 deg/s, to a cycle
    finally:
        assert client.call("servo_move", relFlag=0)["errorCode"] == "0"
        assert client.call("set_servo_move_filter", filter_type=0)["errorCode"] == "0"


def test_frames_have_slots_0_to_10_and_servo_p_outside_servo_mode_is_refused_as_recorded(client):
    eleven = client.call("set_tool_offsets", id=11, name="x", tooloffset=[0, 0, 10, 0, 0, 0])
    assert eleven["errorCode"] == "1" and "[1, 10]" in eleven["errorMsg"]
    assert client.call("set_tool_id", tool_id=11)["errorCode"] == "1"
    assert len(client.call("get_tool_offsets")["tool_offsets"]) == 11
    servo_p = client.call("servo_p", catPosition=[0] * 6, relFlag=1, stepNum=1)
    assert (servo_p["errorCode"], servo_p["errorMsg"]) == (
        "-1", "servop command can only be excuted in servo move mode")
