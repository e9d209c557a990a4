"""Client compatibility: a small client written the way public JAKA clients are (it searches the
reply text for ``"errorCode": "`` and reads replies by fixed key, sends compact JSON with the
SDK's extra keys) runs a whole session against the emulator as a subprocess in the profile of
the arm such clients were tested on (the recorded Zu 5s, fw 1.5.14: it starts powered off),
every step ok."""
from __future__ import annotations

import json
import socket
import time

import pytest

from jaka_driver.emulator.process import EmulatorProcess


class PublicStyleClient:
    """As public clients do it: one socket, compact requests, the reply read until it parses,
    success judged by text search."""

    def __init__(self, host: str, port: int):
        self.sock = socket.create_connection((host, port), timeout=30)

    def send(self, cmd: str, **fields) -> dict:
        self.sock.sendall(json.dumps({"cmdName": cmd, **fields}, separators=(",", ":")).encode())
        text = ""
        while True:
            text += self.sock.recv(65536).decode()
            try:
                reply = json.loads(text)
                break
            except ValueError:
                continue
        start = text.find('"errorCode": "')
        assert start >= 0, f"{cmd}: no '\"errorCode\": \"' in {text!r}"
        code = text[start + len('"errorCode": "')]
        assert code == "0", f"{cmd} failed: {text}"
        return reply

    def close(self) -> None:
        self.sock.close()


@pytest.fixture(scope="module")
def emulator():
    proc = EmulatorProcess("zu5", profile="zu5s-1.5.14").start()
    yield proc
    proc.stop()


def test_a_whole_session_completes(emulator):
    c = PublicStyleClient(emulator.host, emulator.command_port)
    try:
        # it starts as the recorded Zu 5s did: powered off, disabled
        state = c.send("get_robot_state")
        assert (state["power"], state["enable"]) == ("powered_off", "robot_disabled")
        assert "emulator" in c.send("get_version", sdk_version="2.1.14")["robot_name"]
        c.send("power_on")
        c.send("enable_robot")
        state = c.send("get_robot_state")
        assert (state["power"], state["enable"]) == ("powered_on", "robot_enabled")
        home = c.send("get_joint_pos")["joint_pos"]
        a = list(home)
        a[0] += 5.0
        # joint and linear moves back to back: each acknowledged, queued, then waited on
        c.send("joint_move", relFlag=0, jointPosition=a, speed=30.0, accel=100.0,
               executing_line_id=0, tol=0.0)
        c.send("joint_move", relFlag=0, jointPosition=home, speed=30.0, executing_line_id=0)
        c.send("wait_complete")
        tcp = c.send("get_tcp_pos")["tcp_pos"]
        up = list(tcp)
        up[2] += 20.0
        c.send("moveL", relFlag=0, cartPosition=up, speed=50.0, accel=200.0, ori_vel=30.0,
               ori_acc=60.0, executing_line_id=0, tol=0.0)
        c.send("end_move", endPosition=tcp, speed=20.0, accel=50.0)
        c.send("wait_complete")
        assert c.send("get_motion_state")["inpos"] is True
        # servo mode: 125 servo_j at 8 ms
        c.send("servo_move", relFlag=1)
        assert c.send("is_in_servomove")["in_servomove"] is True
        start = time.monotonic()
        for k in range(125):
            c.send("servo_j", relFlag=1, jointPosition=[0, 0, 0, 0, 0, 0.01], stepNum=1)
            delay = start + (k + 1) * 0.008 - time.monotonic()
            if delay > 0:
                time.sleep(delay)
        c.send("servo_move", relFlag=0)
        q = c.send("get_joint_pos")["joint_pos"]
        assert abs(q[5] - (home[5] + 1.25)) < 0.2   # deg: 125 × 0.01°
        # IO, frames, payload, collision level
        c.send("set_digital_output", type=0, index=1, value=1)
        assert c.send("get_digital_output", type=0, index=1)["value"] == 1
        c.send("set_analog_output", type=0, index=7, value=2.5)
        assert c.send("get_analog_output", type=0, index=7)["value"] == 2.5
        c.send("set_tool_offsets", tooloffset=[0, 0, 100, 0, 0, 0], id=1, name="t")
        c.send("set_tool_id", tool_id=1)
        c.send("set_user_offsets", userffset=[300, 0, 50, 0, 0, 0], id=1, name="u")
        c.send("set_user_id", user_frame_id=1)
        # frames read back by id: row 1 is user frame 1 (row 0 the base itself)
        users = c.send("get_user_offsets")["user_offsets"]
        assert len(users) == 11 and users[1][:3] == pytest.approx([300.0, 0.0, 50.0])
        c.send("set_tool_id", tool_id=0)
        c.send("set_user_id", user_frame_id=0)
        c.send("set_payload", mass=1.50, centroid=[0, 0, 50])
        c.send("set_clsn_sensitivity", sensitivityVal=3)
        c.send("stop_program")
        c.send("disable_robot")
        c.send("power_off")
    finally:
        c.close()
