"""Network-loss handling and the mounting angle (§11) as JAKA's SDK writes them on the wire —
the fixtures are the requests measured from JAKA's SDK 2.1.14 (docs/protocol.md, "Network loss",
"Mounting"), typed in here from that record, not produced by our encoders."""
import json
import math

import pytest

from jaka_driver.protocol import commands as c
from jaka_driver.protocol import installation
from jaka_driver.protocol.errors import InvalidArgument, ProtocolError
from jaka_driver.protocol.replies import parse_reply
from jaka_driver.protocol.network_loss import NetworkLossAction, set_network_exception_handle

# §11, as the SDK sent it: set_network_exception_handle(100 ms, MOT_PAUSE)
NETWORK_HANDLE = '{"cmdName":"set_network_exception_handle","motType":1,"timeLimit":100.0}'


def test_network_handle_is_the_sdks_request_byte_for_byte():
    ours = c.encode(set_network_exception_handle(100.0, NetworkLossAction.PAUSE))
    assert ours == NETWORK_HANDLE.encode()
    theirs = json.loads(NETWORK_HANDLE)
    assert type(json.loads(ours)["motType"]) is int and type(theirs["timeLimit"]) is float


@pytest.mark.parametrize("word, mot_type", [("keep", 0), ("pause", 1), ("ABORT", 2)])
def test_network_loss_actions_are_the_sdks_mot_types(word, mot_type):
    action = NetworkLossAction.named(word)
    assert int(action) == mot_type
    assert json.loads(c.encode(set_network_exception_handle(5, action)))["motType"] == mot_type


@pytest.mark.parametrize("call", [lambda: NetworkLossAction.named("stop"),
                                  lambda: set_network_exception_handle(100.0, 3),
                                  lambda: set_network_exception_handle(-1.0, 2),
                                  lambda: set_network_exception_handle(float("nan"), 2)])
def test_a_wrong_network_handle_is_refused_before_sending(call):
    with pytest.raises(InvalidArgument):
        call()


# §11, as the SDK sent it: set_installation_angle(0.5 rad, 1.0 rad) — deg, 16 digits
INSTALLATION = ('{"angleX":28.64788975654116,"angleZ":57.29577951308232,'
                '"cmdName":"set_installation_angle"}')


def test_installation_angle_is_the_sdks_request_in_degrees():
    ours = json.loads(c.encode(installation.set_installation_angle(0.5, 1.0)))
    theirs = json.loads(INSTALLATION)
    assert ours == theirs            # the same numbers, to the last of 16 digits
    assert c.encode(installation.get_installation_angle()) == \
        b'{"cmdName":"get_installation_angle"}'


def test_installation_reply_reads_quaternion_scalar_first_and_rpy_in_degrees():
    reply = parse_reply({"errorCode": "0", "errorMsg": "", "cmdName": "get_installation_angle",
                         "installation_angle": [[0.7071067811865476, 0.7071067811865475, 0.0,
                                                 0.0], [90.0, 0.0, 0.0]]})
    reading = installation.reply_installation_angle(reply)
    assert reading.quaternion == pytest.approx([0.7071067811865475, 0, 0, 0.7071067811865476])
    assert reading.rpy == pytest.approx([math.pi / 2, 0, 0])


@pytest.mark.parametrize("shape", [[1, 0, 0, 0, 0, 0, 0], {"q": 1}, [[1, 0, 0], [0, 0, 0]]])
def test_a_malformed_installation_reply_is_a_protocol_error(shape):
    reply = parse_reply({"errorCode": "0", "installation_angle": shape})
    with pytest.raises(ProtocolError):
        installation.reply_installation_angle(reply)
