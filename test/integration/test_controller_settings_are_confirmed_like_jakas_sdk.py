"""The controller backend against the scripted fake controller (test/support/fake_controller.py,
which answers from the fixtures in test/data/, not the emulator): a setting is believed only once the
controller reports it, as JAKA's SDK reads it back — drag mode through torque_control_enable and
get_drag_status, servo mode through is_in_servomove (fw 1.5.14 acknowledges servo_move while
moves are queued and stays out of it), the active tool and user frame through get_curr_*_id, an
output through its get command; the recorded servo_j refusal outside servo mode is -8; drag mode
is refused where the twin refuses it, with its codes; tool 11 is refused before anything is
sent."""
from __future__ import annotations

import threading

import numpy as np
import pytest

from support.fake_controller import backend, fake  # noqa: F401 - fixtures
from support.fake_controller import foreground
from support.ros_harness import wait_until

from jaka_driver.common.results import Code
from jaka_driver.common.transforms import pose_to_matrix


def names_after(fake, count):
    """cmdNames of the requests received after the first ``count`` (the background program
    state poll's left out)."""
    with fake.lock:
        return [r["cmdName"] for r in foreground(fake.requests[count:])]


def sent_so_far(fake):
    with fake.lock:
        return len(fake.requests)


# ---- drag mode ---------------------------------------------------------------------------------

def test_drag_mode_goes_on_and_off_through_torque_control_enable_read_back_by_get_drag_status(
        fake, backend):
    before = sent_so_far(fake)
    result = backend.set_drag_mode(True)
    assert result.ok, result.message
    assert names_after(fake, before)[:2] == ["torque_control_enable", "get_drag_status"]
    assert fake.received("torque_control_enable")[-1] == {"cmdName": "torque_control_enable",
                                                          "enable_flag": 1}
    assert fake.drag and wait_until(lambda: backend.state().drag_mode, 1.0)
    assert backend.set_drag_mode(True).message == "drag mode already on"

    before = sent_so_far(fake)
    assert backend.set_drag_mode(False).ok
    assert names_after(fake, before)[:2] == ["torque_control_enable", "get_drag_status"]
    assert fake.received("torque_control_enable")[-1]["enable_flag"] == 0
    assert not fake.drag and wait_until(lambda: not backend.state().drag_mode, 1.0)


def test_drag_mode_is_refused_in_servo_mode_and_while_moving_with_the_twins_codes(fake, backend):
    assert backend.servo_enable(True).ok
    refused = backend.set_drag_mode(True)
    assert refused.code == Code.WRONG_MODE and "servo mode" in refused.message
    assert backend.servo_enable(False).ok

    fake.move_time = 2.0
    q = backend.state().joint_position + 0.1
    started = backend.start_joint_move(q, 1.0, 4.0)
    assert started.ok
    refused = backend.set_drag_mode(True)
    assert refused.code == Code.BUSY and "moves" in refused.message
    assert fake.received("torque_control_enable") == [] and not fake.drag
    backend.stop_move()


# ---- servo mode ----------------------------------------------------------------------------------

def test_servo_mode_is_believed_only_when_is_in_servomove_says_so(fake, backend):
    # a move queued by someone else (the pendant, another client) runs on the controller
    fake.move_time = 1.5
    q = np.degrees(backend.state().joint_position + 0.05).tolist()
    assert backend.link.call({"cmdName": "joint_move", "relFlag": 0, "jointPosition": q,
                              "speed": 10.0, "accel": 50.0}).ok
    refused = backend.servo_enable(True)
    # recorded on fw 1.5.14: servo_move is acknowledged ("0"), is_in_servomove stays false
    assert refused.code == Code.CONTROLLER_REJECTED, refused.message
    assert "is_in_servomove still reads False" in refused.message
    assert fake.received("servo_move")[-1]["relFlag"] == 1
    assert not backend.state().servo_mode
    assert len(fake.received("is_in_servomove")) >= 5   # polled for the SDK's 1 s

    assert wait_until(lambda: not fake.queue, 3.0)
    assert backend.servo_enable(True).ok
    assert backend.state().servo_mode and fake.servo


def test_servo_j_outside_servo_mode_is_minus_8_from_the_recorded_refusal(fake, backend):
    assert backend.servo_enable(True).ok
    fake.servo = False   # the controller left servo mode by itself
    q = backend.state().joint_position
    refused = backend.servo_j(q)
    assert refused.code == Code.SERVO_MODE_OFF
    assert "servoj command can only be excuted in servo move mode" in refused.message
    assert not backend.state().servo_mode


# ---- frames, payload, IO -------------------------------------------------------------------------

def test_a_frame_the_backend_sets_is_stored_by_id_activated_and_read_back(fake, backend):
    pose = pose_to_matrix([10, 20, 150, 0, 0, 0.5], rotation="rpy", length_scale=1e-3)
    before = sent_so_far(fake)
    assert backend.set_tool_frame(3, pose).ok
    assert names_after(fake, before)[:3] == ["set_tool_offsets", "set_tool_id",
                                             "get_curr_tool_id"]
    np.testing.assert_allclose(fake.offsets["tool"][3], [10, 20, 150, 0, 0, np.degrees(0.5)])
    assert fake.active["tool"] == 3
    assert wait_until(lambda: backend.state().tool_id == 3, 1.0)
    np.testing.assert_allclose(backend.frames()[0], pose, atol=1e-12)
    # activating its own frame is no news: the table is not read again for it
    assert "get_tool_offsets" not in names_after(fake, before)

    user = pose_to_matrix([300, -200, 50, 0, 0, 0.3], rotation="rpy", length_scale=1e-3)
    assert backend.set_user_frame(2, user).ok
    assert fake.received("set_user_offsets")[-1]["id"] == 2 and fake.active["user"] == 2
    assert fake.received("get_curr_user_id")
    assert wait_until(lambda: backend.state().user_id == 2, 1.0)
    np.testing.assert_allclose(backend.frames()[1], user, atol=1e-12)


def test_payload_activates_its_tool_confirmed_then_sets_the_payload(fake, backend):
    before = sent_so_far(fake)
    assert backend.set_payload(2, 1.5, np.array([0.0, 0.0, 0.05])).ok
    assert names_after(fake, before)[:3] == ["set_tool_id", "get_curr_tool_id", "set_payload"]
    assert fake.received("set_payload")[-1]["centroid"] == pytest.approx([0, 0, 50])
    assert fake.active["tool"] == 2


@pytest.mark.parametrize("call", [
    lambda b: b.set_tool_frame(11, np.eye(4)),
    lambda b: b.set_payload(11, 1.0, np.zeros(3)),
    lambda b: b.set_user_frame(11, np.eye(4)),
], ids=["set_tool_frame", "set_payload", "set_user_frame"])
def test_frame_id_11_is_refused_before_anything_is_sent(fake, backend, call):
    before = sent_so_far(fake)
    refused = call(backend)
    assert refused.code == Code.INVALID_PARAMETER and "1-10" in refused.message
    assert names_after(fake, before) == []


def test_an_output_is_read_back_after_it_is_set(fake, backend):
    before = sent_so_far(fake)
    assert backend.set_io("digital", 1, 1, 1.0).ok
    assert names_after(fake, before)[:2] == ["set_digital_output", "get_digital_output"]
    assert fake.received("get_digital_output")[-1] == {"cmdName": "get_digital_output",
                                                       "type": 1, "index": 2}
    assert backend.set_io("analog", 0, 6, -2.5).ok
    assert fake.received("get_analog_output")[-1]["index"] == 7
    read = backend.get_io("digital", 1, 1, 1)
    assert read.ok and read.value == 1.0
    read = backend.get_io("analog", 0, 0, 0)
    assert read.ok and fake.received("get_analog_input")[-1]["index"] == 1


def test_every_setting_of_a_session_reads_back_at_once(fake, backend):
    """Calls from many threads at once: each confirmation finds its own setting."""
    results = []

    def run(i):
        results.append(backend.set_io("digital", 0, i, 1.0))
    threads = [threading.Thread(target=run, args=(i,)) for i in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(5)
    assert len(results) == 8 and all(r.ok for r in results), [r.message for r in results]
    assert all(fake.io[("digital_output", 0, i + 1)] == 1 for i in range(8))
