"""A named profile selects what differs between the JAKA controllers on record — firmware
version, cabinet IO sizes, push period, start state, the answer to emergency_stop_status — the
default being the controller JAKA's SDK and ROS 2 driver are written for (fw 1.7.2), the
recorded Zu 5s on fw 1.5.14 one option away; --start and --period override a profile, and
--help lists every profile with what it sets (and tcp-doc, fw-1.7.2's former name)."""
from __future__ import annotations

import socket
import subprocess
import sys
import time

import pytest

from support.raw_client import call_once

from jaka_driver.emulator import Emulator
from jaka_driver.emulator.profiles import (ALIASES, DEFAULT_PROFILE, PROFILES, START_WORDS,
                                           profile_named)

ROBOT_STATE = {"off": ("powered_off", "robot_disabled"), "on": ("powered_on", "robot_disabled"),
               "enabled": ("powered_on", "robot_enabled")}


def _packets_per_second(port: int, seconds: float = 1.0) -> float:
    data = b""
    with socket.create_connection(("127.0.0.1", port), timeout=2) as sock:
        sock.recv(65536)                 # the first packet starts the count
        t0 = time.monotonic()
        while time.monotonic() - t0 < seconds:
            data += sock.recv(65536)
        elapsed = time.monotonic() - t0
    return data.count(b'{"len": ') / elapsed


def test_help_lists_every_profile_and_what_it_sets():
    out = subprocess.run([sys.executable, "-m", "jaka_driver.emulator", "--help"],
                         capture_output=True, text=True, timeout=60, check=True).stdout
    for profile in PROFILES.values():
        assert profile.name in out and " ".join(profile.describe().split()) in " ".join(out.split())
    assert f"default {DEFAULT_PROFILE}" in out
    assert "tcp-doc: the former name of fw-1.7.2" in out


def test_the_default_is_the_controller_jakas_sdk_is_written_for():
    default = PROFILES[DEFAULT_PROFILE]
    # JAKA's ROS 2 driver asks for firmware 1.7.1 or newer; JAKA's SDK asks
    # emergency_stop_status inside its moves and fails them if it does not answer
    assert DEFAULT_PROFILE == "fw-1.7.2" and default.version.startswith("1.7.2_")
    assert not default.estop_status_fails
    recorded = profile_named("zu5s-1.5.14")
    assert (recorded.version, recorded.period, recorded.start, recorded.estop_status_fails) \
        == ("1.5.14_13_X64", 0.030, "off", True)
    assert profile_named("tcp-doc") is default and ALIASES == {"tcp-doc": "fw-1.7.2"}


@pytest.mark.parametrize("name", list(PROFILES))
def test_each_profile_starts_pushes_and_answers_as_it_says(name):
    profile = PROFILES[name]
    with Emulator("zu5", command_port=0, status_port=0, profile=name) as emu:
        state = call_once(emu.command_port, "get_robot_state")
        assert (state["power"], state["enable"]) == ROBOT_STATE[profile.start]
        assert call_once(emu.command_port, "get_version")["version"] == profile.version
        estop = call_once(emu.command_port, "emergency_stop_status")
        if profile.estop_status_fails:
            assert estop == {"errorCode": "1", "errorMsg": "Exception:function call failed"}
        else:
            assert estop["errorCode"] == "0" and estop["emergency_stop"] == 0
        packet = call_once(emu.command_port, "get_data")
        assert len(packet["din"]) == profile.io_sizes[("digital", 0, 0)]
        assert len(packet["ain"]) == profile.io_sizes[("analog", 0, 0)]
        assert emu.period == profile.period
        # Wall clock: the emulator's status push is paced in wall time, as a controller's
        # (no sim time on the wire); counted over a wall window (monotonic, µs).
        # Never faster than the period; a broadcaster woken later than a whole period
        # resynchronises instead of bursting, so a busy machine costs packets: the lower bound
        # allows it half of them, still far from the other profiles' periods (8 and 30 ms)
        rate = _packets_per_second(emu.status_port)
        assert 0.5 / profile.period < rate < 1.15 / profile.period, (name, rate)


def test_start_and_period_override_the_profile():
    with Emulator("zu5", command_port=0, status_port=0, start="on", period=0.05) as emu:
        state = call_once(emu.command_port, "get_robot_state")
        assert (state["power"], state["enable"]) == ("powered_on", "robot_disabled")
        assert 15 < _packets_per_second(emu.status_port) < 23


def test_an_unknown_profile_or_start_state_is_refused_with_the_known_ones():
    with pytest.raises(ValueError, match="fw-1.7.2, zu5s-1.5.14, large-io"):
        Emulator("zu5", command_port=0, status_port=0, profile="zu5s-9.9")
    with pytest.raises(ValueError, match="enabled"):
        Emulator("zu5", command_port=0, status_port=0, start="half")
    assert set(START_WORDS) == {"off", "on", "enabled"}
