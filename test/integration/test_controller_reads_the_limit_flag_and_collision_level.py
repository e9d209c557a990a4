"""The smaller reads on a controller (docs/interface.md, "get_collision_level", "Topics"):
``on_soft_limit`` of every status packet becomes ``RobotState.on_limit``; the collision level is
read with ``get_clsn_sensitivity`` → ``sensitivityLevel``, the reply JAKA's SDK reads (§11: its
``errorCode`` a string), and a refusal is the contract's 2. Against a fake controller scripted
from the recorded packet and the SDK's replies, and end to end through the emulator, whose
packet says ``on_soft_limit`` 1 while a joint of its twin is within 0.1° of its limit."""
import time

import numpy as np
import pytest

from support.emulated_arm import driver_on_emulator
from support.fake_controller import FakeController, start_backend

from jaka_driver.common.results import Code

# §11: get_collision_level sends get_clsn_sensitivity and reads sensitivityLevel
CLSN_REPLY = {"errorCode": "0", "errorMsg": "", "cmdName": "get_clsn_sensitivity",
              "sensitivityLevel": 3}


def until(condition, timeout=2.0):
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.01)
    return condition()


def test_every_packets_soft_limit_flag_reaches_the_state():
    with FakeController() as fake:
        backend = start_backend(fake)
        try:
            assert backend.state().on_limit is False
            fake.packet["on_soft_limit"] = 1
            assert until(lambda: backend.state().on_limit)
            fake.packet["on_soft_limit"] = 0
            assert until(lambda: not backend.state().on_limit)
        finally:
            backend.shutdown()


def test_the_collision_level_is_read_as_jakas_sdk_reads_it():
    with FakeController() as fake:
        backend = start_backend(fake)
        try:
            fake.replies["get_clsn_sensitivity"] = dict(CLSN_REPLY)
            result = backend.collision_level()
            assert (result.code, result.value) == (1, 3)
            assert fake.received("get_clsn_sensitivity") == [{"cmdName": "get_clsn_sensitivity"}]
            fake.replies["get_clsn_sensitivity"] = {"errorCode": "1", "errorMsg": "busy",
                                                    "cmdName": "get_clsn_sensitivity"}
            refused = backend.collision_level()
            assert refused.code == Code.CONTROLLER_REJECTED and "busy" in refused.message
        finally:
            backend.shutdown()


def test_through_the_emulator_the_twins_limit_and_level_reach_the_driver():
    with driver_on_emulator(programs=None) as (emu, driver):
        assert driver.set_collisionlevel(True, 60).ok
        assert driver.collision_level().value == 3 == emu.backend.collision_level().value
        assert not driver.state().on_limit
        near = emu.model.home.copy()
        near[2] = emu.model.lower[2] + np.radians(0.05)      # J3 0.05° inside its limit
        assert driver.joint_move(list(near), 3.0, 10.0).ok
        assert until(lambda: driver.state().on_limit) and emu.backend.state().on_limit
        near[2] += np.radians(0.2)                           # 0.25° inside: off the limit
        assert driver.joint_move(list(near), 3.0, 10.0).ok
        assert until(lambda: not driver.state().on_limit)
