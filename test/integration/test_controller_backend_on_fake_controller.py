"""The controller backend against a scripted fake controller that answers exactly as the
transcripts in test/data/ do (not the emulator): the wire carries 1-based IO indices and
``userffset``, replies of either layout are read, blocking moves end on ``get_motion_state`` and
``inpos``, a second move while one runs is refused without reaching the controller, and status
arrives from port 10000, port 10004 (zlib) or both — also with the 36 keys of the packet
recorded on fw 1.5.14 (test/data/status_packet_fw1.5.14.json), which lacks ``instVel``,
``motion_line`` and the fieldbus arrays."""
from __future__ import annotations

import json
import re
import threading

import numpy as np
import pytest

from support.fake_controller import backend, fake  # noqa: F401 - fixtures
from support.fake_controller import (RECORDED_PACKET, FakeController, load_status_packet,
                                     load_transcript, start_backend)
from support.move_helpers import run_move
from support.ros_harness import wait_until

from jaka_driver.common.results import Code
from jaka_driver.common.transforms import pose_to_matrix, rpy_to_matrix

START_DEG = json.loads(load_status_packet())["joint_actual_position"]


def _without_strings(text: str) -> str:
    return re.sub(r'"(?:\\.|[^"\\])*"', '""', text)


def test_the_fixtures_are_in_the_controllers_layout():
    for packet_text in (load_status_packet(), load_status_packet(RECORDED_PACKET)):
        packet = json.loads(packet_text)
        assert packet_text.startswith('{"len": ') and packet["len"] == len(packet_text.encode())
        assert packet_text == json.dumps(packet)   # spaces after ':' and ','
    full, recorded = json.loads(load_status_packet()), json.loads(load_status_packet(RECORDED_PACKET))
    # the recorded fw 1.5.14 packet: 36 keys (test_recorded_packet_is_fact_37.py); those the
    # full packet has too, as the full packet has them
    assert len(recorded) == 36
    assert all(recorded[k] == full[k] for k in recorded if k != "len" and k in full)
    for request, reply, _ in load_transcript():
        assert " " not in _without_strings(request), request   # compact
        decoded = json.loads(reply)
        assert list(decoded)[:2] == ["errorCode", "errorMsg"], reply
        assert ", " in reply and '"errorCode": "' in reply
        # every non-integer number with 6 decimals, as a real controller writes them
        assert not re.search(r"\d\.(\d{1,5}|\d{7,})\b", _without_strings(reply)), reply


@pytest.mark.parametrize("source", ["stream", "request", "both"])
def test_state_comes_from_port_10000_port_10004_or_both(source):
    with FakeController(stream=source != "request", data_port=source != "stream") as fake:
        backend = start_backend(fake, source=source)
        try:
            st = backend.state()
            np.testing.assert_allclose(st.joint_position, np.radians(START_DEG), atol=1e-9)
            x, y, z, rx, ry, rz = json.loads(load_status_packet())["actual_position"]
            np.testing.assert_allclose(st.tcp_pose[:3, 3], [x / 1e3, y / 1e3, z / 1e3])
            np.testing.assert_allclose(st.tcp_pose[:3, :3],
                                       rpy_to_matrix(*np.radians([rx, ry, rz])), atol=1e-12)
            assert st.powered and st.enabled
            ports = {"stream": [fake.status_port], "request": [fake.data_port],
                     "both": [fake.status_port, fake.data_port]}[source]
            for port in ports:
                assert wait_until(
                    lambda: backend.describe()[f"status port {port} packets"] > 10, 2.0)
            assert bool(fake.received("data_request")) == (source != "stream")
        finally:
            backend.shutdown()


def test_io_index_is_one_based_on_the_wire(fake, backend):
    assert backend.set_io("digital", 0, 2, 1.0).ok
    assert fake.received("set_digital_output")[-1]["index"] == 3
    assert backend.set_io("analog", 0, 6, 2.5).ok    # cabinet analog output 7 of the wire
    assert fake.received("set_analog_output")[-1]["index"] == 7
    read = backend.get_io("digital", 0, 0, 0)
    assert read.ok and read.value == 0 and fake.received("get_digital_input")[-1]["index"] == 1
    read = backend.get_io("analog", 1, 0, 6)
    assert read.ok and read.value == 2.5 and fake.received("get_analog_output")[-1]["index"] == 7


def test_user_frame_goes_out_as_userffset(fake, backend):
    pose = pose_to_matrix([300, -200, 50, 0, 0, 0.3], rotation="rpy", length_scale=1e-3)
    assert backend.set_user_frame(1, pose).ok
    sent = fake.received("set_user_offsets")[-1]
    assert "userffset" in sent and "useroffset" not in sent
    np.testing.assert_allclose(sent["userffset"], [300, -200, 50, 0, 0, np.degrees(0.3)])
    assert fake.received("set_user_id")[-1]["user_frame_id"] == 1


@pytest.mark.parametrize("layout", ["controller", "compact"])
def test_a_blocking_move_ends_when_the_queue_is_done(layout):
    with FakeController(move_time=0.4, layout=layout) as fake:
        backend = start_backend(fake)
        try:
            target = np.radians(START_DEG) + 0.2
            result = run_move(backend.start_joint_move(target, 1.0, 4.0))
            assert result.ok, result.message
            np.testing.assert_allclose(backend.state().joint_position, target, atol=1e-9)
            # it waited for the queue, asking the controller, not only reading the stream
            assert len(fake.received("get_motion_state")) >= 3
            assert fake.received("joint_move")[-1]["jointPosition"] == \
                pytest.approx(np.degrees(target).tolist())
        finally:
            backend.shutdown()


def test_a_move_while_one_runs_is_refused_and_never_reaches_the_controllers_queue(fake,
                                                                                    backend):
    first = {}
    target = np.radians(START_DEG) + 0.1
    runner = threading.Thread(target=lambda: first.update(
        r=run_move(backend.start_joint_move(target, 1, 4))))
    runner.start()
    try:
        assert wait_until(lambda: fake.received("joint_move"), 2.0)
        second = backend.start_joint_move(np.radians(START_DEG), 1.0, 4.0)
        assert second.code == Code.BUSY and "still running" in second.message
    finally:
        runner.join(10)
    assert first["r"].ok and len(fake.received("joint_move")) == 1


def test_stop_move_empties_the_controllers_queue_and_ends_the_wait(fake, backend):
    outcome = {}
    target = np.radians(START_DEG) - 0.1
    runner = threading.Thread(target=lambda: outcome.update(
        r=run_move(backend.start_joint_move(target, 1, 4))))
    fake.move_time = 5.0
    runner.start()
    assert wait_until(lambda: fake.received("joint_move"), 2.0)
    assert backend.stop_move().ok
    runner.join(3.0)
    assert not runner.is_alive()
    assert outcome["r"].code == Code.MOTION_STOPPED and fake.received("stop_program")
    assert not fake.queue


def test_a_controller_refusal_is_code_2_with_its_message(fake, backend):
    backend.link.call({"cmdName": "get_version"})   # the link works
    reply = backend.send.call({"cmdName": "joint_move", "relFlag": 0, "speed": 20.0,
                               "accel": 50.0, "jointPosition": [400.0, 0, 0, 0, 0, 0]})
    assert not reply.ok and reply.error_code == "2"
    assert reply.error_msg == "call joint_move failed"



def test_the_recorded_fw_1_5_14_packet_gives_the_backend_all_it_needs():
    packet = json.loads(load_status_packet(RECORDED_PACKET))
    with FakeController(packet=RECORDED_PACKET, move_time=0.3) as fake:
        backend = start_backend(fake)
        try:
            assert wait_until(lambda: backend.view.latest is not None, 2.0)
            # the recording has no commanded joints (``joint_position``): the parser lists them
            # missing, and the backend reads nothing of them
            assert backend.view.latest.missing == ("joint_position",), backend.view.latest.missing
            st = backend.state()
            np.testing.assert_allclose(st.joint_position, np.radians(START_DEG), atol=1e-9)
            assert st.powered and st.enabled and not st.moving and st.error_code == 0
            # effort from monitor_data's joint rows; no instVel: speed from the joints, at rest 0
            np.testing.assert_allclose(st.joint_effort, [row[9] for row in
                                                         packet["monitor_data"][5]])
            np.testing.assert_allclose(st.joint_velocity, np.zeros(6), atol=1e-12)
            assert backend.describe()["homed"] == [1] * 9
            # a blocking move ends on the queue and inpos, without motion_line
            target = np.radians(START_DEG) + 0.1
            assert run_move(backend.start_joint_move(target, 1.0, 4.0)).ok
            np.testing.assert_allclose(backend.state().joint_position, target, atol=1e-9)
        finally:
            backend.shutdown()
