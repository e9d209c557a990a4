"""JAKA's SDK 2.1.14 asks ``emergency_stop_status`` inside ``get_robot_state``, ``is_in_estop``,
``joint_move``, ``linear_move``, ``jog`` and ``jog_stop`` — one request per call — and returns 2
when that answer is not a success (test/jaka_sdk_model.py, from the measured evidence).

Against ``jaka_emulator`` started with no options (fw-1.7.2, the controller the SDK is written
for) all six complete. Against the recorded fw 1.5.14 (``--profile zu5s-1.5.14``), which answers
``emergency_stop_status`` with the recorded exception, all six return 2 — and the moves and the
jog were acknowledged and run all the same, as they did for JAKA's SDK on the wire. Other SDK
calls (login, power, the status over port 10004, IO) complete on both."""
from __future__ import annotations

import json

import numpy as np
import pytest

from support.jaka_sdk_model import ABS, ASKS_ESTOP, CONTINUE, COORD_JOINT, RC_FAILED, RC_OK, JakaSdk
from support.ros_harness import wait_until

from jaka_driver.emulator.process import EmulatorProcess

RECORDED_EXCEPTION = {"errorCode": "1", "errorMsg": "Exception:function call failed"}


@pytest.fixture(scope="module", params=[None, "zu5s-1.5.14"],
                ids=["no options", "zu5s-1.5.14"])
def sdk(request):
    """An SDK handle on an emulator subprocess: with no option but its ports, or the recorded
    fw 1.5.14 profile; powered on and enabled by the SDK as a program would."""
    with EmulatorProcess("zu5", profile=request.param) as emulator:
        handle = JakaSdk("127.0.0.1", emulator.command_port, emulator.data_port)
        try:
            assert handle.login_in()[0] == RC_OK
            assert handle.power_on() == RC_OK and handle.enable_robot() == RC_OK
            handle.profile = request.param
            yield handle
        finally:
            handle.close()


def test_six_sdk_calls_ask_the_estop_and_fail_only_where_it_does_not_answer(sdk):
    rcs, sent = {}, {}

    def run(name, call):
        before = len(sdk.sent)
        result = call()
        rcs[name] = result[0] if isinstance(result, tuple) else result
        sent[name] = [json.loads(text)["cmdName"] for text in sdk.sent[before:]]

    def status():
        rc, st = sdk.get_robot_status()
        assert rc == RC_OK
        return st

    def joints():
        # get_joint_pos: the recorded fw 1.5.14 packet has no ``joint_position``, which is what
        # the SDK's RobotStatus reads its joints from (it reads zeros there, as on that arm)
        rc, reply = sdk.call("get_joint_pos")
        assert rc == RC_OK
        return np.radians(reply["joint_pos"])

    start = status()
    assert start.powered_on == 1 and start.enabled
    q0, tcp0 = joints(), np.array(start.cartesiantran_position)
    run("get_robot_state", sdk.get_robot_state)
    run("is_in_estop", sdk.is_in_estop)
    run("joint_move", lambda: sdk.joint_move(q0 + [0.1, 0, 0, 0, 0, 0], ABS, 1.0, 4.0))
    assert sdk.wait_inpos(10.0)
    moved = joints()
    run("linear_move", lambda: sdk.linear_move([*(tcp0[:3] + [0, 0, 20.0]), *tcp0[3:]], ABS,
                                               50.0, 200.0))
    assert sdk.wait_inpos(10.0)
    lifted, q_lifted = status(), joints()
    run("jog", lambda: sdk.jog(5, CONTINUE, COORD_JOINT, 0.2, 0.0))    # joint 6 at 0.2 rad/s
    jogged = wait_until(lambda: joints()[5] - q_lifted[5] > 0.01, 5.0)
    run("jog_stop", lambda: sdk.jog_stop(-1))
    stopped = sdk.wait_inpos(2.0)

    # one emergency_stop_status inside each, besides the call's own command
    assert {name: commands.count("emergency_stop_status") for name, commands in sent.items()} \
        == {name: 1 for name in ASKS_ESTOP}
    assert (sent["joint_move"][0], sent["linear_move"][0], sent["jog"][0], sent["jog_stop"][0]) \
        == ("joint_move", "moveL", "jog", "jog")
    if sdk.profile is None:
        assert rcs == {name: RC_OK for name in ASKS_ESTOP}
        assert sdk.call("emergency_stop_status")[1]["emergency_stop"] == 0
    else:
        # why: the recorded fw 1.5.14 answers emergency_stop_status with an exception
        assert rcs == {name: RC_FAILED for name in ASKS_ESTOP}
        assert sdk.call("emergency_stop_status")[1] == RECORDED_EXCEPTION
    # on both, the moves and the jog were acknowledged and ran, and jog_stop stopped the jog
    assert abs(moved[0] - (q0[0] + 0.1)) < 1e-3
    assert abs(lifted.cartesiantran_position[2] - (tcp0[2] + 20.0)) < 0.5
    assert jogged and stopped


def test_the_calls_that_do_not_ask_the_estop_complete_on_both(sdk):
    assert sdk.set_digital_output(0, 1, True) == RC_OK
    assert sdk.get_digital_output(0, 1) == (RC_OK, True)
    assert sdk.set_digital_output(0, 1, False) == RC_OK
    assert sdk.get_robot_status()[0] == RC_OK
    assert sdk.kine_forward([0.0, 1.5, -1.5, 1.5, 1.5, 0.0])[0] == RC_OK
