"""A scripted fake JAKA controller for tests: it answers as the fixtures in test/data/ do.

Not the emulator, on purpose: the controller backend is tested here against something its authors
did not write to agree with it. Every reply is the transcript's reply for that ``cmdName``
(test/data/command_transcript.txt), with only the values that must follow the script's state
replaced (joints, TCP, the motion queue, IO, power); every status packet is
test/data/status_packet.json (or another packet fixture: ``packet=``, e.g. the recorded fw
1.5.14's 35 keys) with the same values replaced and ``len`` recomputed.

The script: a move is acknowledged at once and queued; each queued move takes ``move_time`` s,
and the arm jumps to its target when it ends (a fake has no kinematics: ``moveL``/``end_move`` set
the TCP, joint moves the joints). ``get_motion_state`` and the packets' ``inpos`` show the queue;
``wait_complete`` answers when it is empty; ``stop_program`` empties it.

What is set reads back, from the reply and the status packet: drag mode (``torque_control_enable``
→ ``get_drag_status``, ``drag_status``), servo mode (``servo_move`` → ``is_in_servomove``), the
frame tables (``set_*_offsets`` → the row of that id in ``get_*_offsets``, which start as the
transcript's tables), the active tool and user frame (``set_*_id`` → ``get_curr_*_id``,
``current_*_id``), IO, payloads, the speed ratio. The recorded refusals of fw 1.5.14 are played
where they were recorded: ``servo_j`` outside servo mode answers the transcript's ``-1``,
``servo_move`` while moves are queued is acknowledged and servo mode is not entered.
:meth:`FakeController.on_pendant` changes frames as an operator at the teach pendant would, and
``raw_replies`` makes the next reply to a command any bytes at all.

The torque sensor and force control (:class:`FakeTorqueSensor`, ``fake.sensor``) answer as
sdk_wire_formats §5 gives the replies JAKA's SDK reads (no transcript records them): every set
shows in its get, ``set_torque_sensor_mode`` in the packet's ``torqsensor`` status,
``enable_admittance_ctrl`` / ``disable_force_control`` in ``get_tool_drive_stat``;
identification answers the statuses a test scripts, then its result. The packet's
``torqsensor`` keeps the recorded layout — two wrenches, ``[status, errcode, actual,
general]`` — with the values a test sets (``three_vectors`` adds ``real``).

Tests take the fixtures ``fake`` and ``backend`` (a ControllerBackend connected to it) from here.

Ports: command (10001 role), status stream (10000 role, optional), data_request (10004 role,
optional), all on 127.0.0.1 with free port numbers. ``layout="compact"`` answers without spaces
(an older firmware's layout), to prove readers do not depend on the spaces.
"""
from __future__ import annotations

import copy
import json
import socket
import threading
import time
import zlib
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

import pytest

from jaka_driver.protocol.tcp_server import TcpServer

DATA = Path(__file__).resolve().parents[1] / "data"     # test/data
PERIOD = 0.008   # s between two status packets


def load_transcript() -> List[Tuple[str, str, str]]:
    """(request text, reply text, note) of every exchange in command_transcript.txt."""
    out, note, request = [], "", None
    for line in (DATA / "command_transcript.txt").read_text().splitlines():
        if line.startswith("# "):
            note = line[2:]
        elif line.startswith("> "):
            request = line[2:]
        elif line.startswith("< "):
            out.append((request, line[2:], note))
            note, request = "", None
    return out


#: the packet fixture of the controller JAKA's SDK reads, and the recorded fw 1.5.14's
PACKET, RECORDED_PACKET = "status_packet.json", "status_packet_fw1.5.14.json"


def load_status_packet(name: str = PACKET) -> str:
    """A status packet fixture, exact text (one line)."""
    return (DATA / name).read_text().strip()


def encode_packet(fields: Dict[str, Any]) -> bytes:
    """A status packet in the controller's layout with a self-consistent ``len``."""
    n = 0
    for _ in range(10):
        text = json.dumps({**fields, "len": n}).encode()
        if len(text) == n:
            return text
        n = len(text)
    raise AssertionError("len did not converge")


#: What the controller backend reads in the background whatever a test does: the program state
#: poll (src/jaka_driver/controller/programs.py, every 0.25 s and after each program command).
#: Tests that compare what one request put on the wire leave these out (:func:`foreground`).
PROGRAM_STATE_POLL = frozenset({"get_program_state", "get_current_line", "get_loaded_program"})


def foreground(requests: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """``requests`` without the program state poll's."""
    return [r for r in requests if r.get("cmdName") not in PROGRAM_STATE_POLL]


class FakeController:
    def __init__(self, *, stream: bool = True, data_port: bool = True, move_time: float = 0.3,
                 layout: str = "controller", packet: str = PACKET):
        self.move_time = move_time
        self.separators = (", ", ": ") if layout == "controller" else (",", ":")
        self.replies: Dict[str, Dict[str, Any]] = {}
        self.refusals: Dict[str, Dict[str, Any]] = {}
        for request_text, reply_text, _ in load_transcript():
            reply = json.loads(reply_text)
            # a reply may lack cmdName (fw 1.5.14's emergency_stop_status): the request names it
            name = json.loads(request_text)["cmdName"]
            table = self.replies if reply["errorCode"] == "0" else self.refusals
            table.setdefault(name, reply)
        self.packet = json.loads(load_status_packet(packet))
        self.joints = list(self.packet["joint_actual_position"])   # deg
        self.tcp = list(self.packet["actual_position"])            # mm, RPY deg
        self.powered, self.enabled, self.servo, self.drag = True, True, False, False
        self.io: Dict[Tuple[str, int, int], float] = {}             # (kind, type, wire index)
        self.offsets = {kind: copy.deepcopy(self.replies[f"get_{kind}_offsets"][f"{kind}_offsets"])
                        for kind in ("tool", "user")}               # row = id: mm, RPY deg
        self.active = {"tool": self.packet["current_tool_id"],
                       "user": self.packet["current_user_id"]}
        self.settings = {"get_payload": {}, "get_rapid_rate": {},
                         "get_tio_vout_param": {}}                  # what a get answers
        self.sensor = FakeTorqueSensor()
        self.raw_replies: Dict[str, bytes] = {}                     # next reply, any bytes
        self.queue: List[Dict[str, Any]] = []                       # moves, the first runs
        self.requests: List[Dict[str, Any]] = []                    # every request decoded
        self.texts: List[str] = []                                  # and as it was sent
        self.lock = threading.RLock()
        self._quit = threading.Event()
        self._servers: List[TcpServer] = []
        self.command_port = self._serve(self._command_client)
        self.status_port = self._serve(self._status_client) if stream else _closed_port()
        self.data_port = self._serve(self._data_client) if data_port else _closed_port()

    # ---- what tests read ----------------------------------------------------------------------
    def received(self, name: str) -> List[Dict[str, Any]]:
        with self.lock:
            return [r for r in self.requests if r.get("cmdName") == name]

    def close(self) -> None:
        self._quit.set()
        for server in self._servers:
            server.stop()

    def __enter__(self) -> "FakeController":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ---- the script ---------------------------------------------------------------------------
    def _advance(self) -> None:
        """End the queued moves whose time is up; start the next one."""
        now = time.monotonic()
        while self.queue:
            move = self.queue[0]
            move.setdefault("ends", now + self.move_time)
            if move["ends"] > now:
                return
            self.queue.pop(0)
            if move["kind"] == "joints":
                self.joints = move["target"]
            else:
                self.tcp = move["target"]
            if self.queue:
                self.queue[0]["ends"] = move["ends"] + self.move_time

    def on_pendant(self, kind: str, frame_id: int, offset=None) -> None:
        """An operator at the teach pendant stores ``offset`` (mm, RPY deg) as ``kind``
        ("tool" or "user") ``frame_id`` and makes it active."""
        with self.lock:
            if offset is not None:
                self.offsets[kind][frame_id] = [float(v) for v in offset]
            self.active[kind] = frame_id

    def answer(self, req: Dict[str, Any]) -> Dict[str, Any]:
        name = req.get("cmdName", "")
        with self.lock:
            self._advance()
            sensor = self.sensor.answer(name, req)
            if sensor is not None:
                return {"errorCode": "0", "errorMsg": "", "cmdName": name, **sensor}
            if name not in self.replies:
                if name in self.refusals:   # recorded only as a non-success
                    return copy.deepcopy(self.refusals[name])
                return {"errorCode": "1", "errorMsg": f"unknown command {name}", "cmdName": name}
            reply = copy.deepcopy(self.replies[name])
            refusal = self._act(name, req, reply)
        return refusal if refusal is not None else reply

    def _act(self, name: str, req: Dict[str, Any], reply: Dict[str, Any]) -> Optional[Dict]:
        if name == "joint_move":
            target = [float(v) for v in req["jointPosition"]]
            if any(abs(v) > 360 for v in target):
                return copy.deepcopy(self.refusals["joint_move"])
            if req.get("relFlag"):
                base = self.queue[-1]["target"] if self.queue and self.queue[-1]["kind"] \
                    == "joints" else self.joints
                target = [a + b for a, b in zip(base, target)]
            self.queue.append({"kind": "joints", "target": target})
            self._advance()
        elif name in ("moveL", "end_move"):
            key = "cartPosition" if name == "moveL" else "endPosition"
            self.queue.append({"kind": "tcp", "target": [float(v) for v in req[key]]})
            self._advance()
        elif name == "stop_program":
            self.queue.clear()
        elif name == "get_motion_state":
            reply.update(inpos=not self.queue, queue=max(0, len(self.queue) - 1),
                         active_queue=len(self.queue))
        elif name == "get_joint_pos":
            reply["joint_pos"] = list(self.joints)
        elif name == "get_tcp_pos":
            reply["tcp_pos"] = list(self.tcp)
        elif name in ("power_on", "power_off"):
            self.powered = name == "power_on"
            self.enabled = self.enabled and self.powered
        elif name in ("enable_robot", "disable_robot"):
            self.enabled = name == "enable_robot"
        elif name == "get_robot_state":
            reply.update(enable="robot_enabled" if self.enabled else "robot_disabled",
                         power="powered_on" if self.powered else "powered_off")
        elif name == "servo_move":
            # recorded on fw 1.5.14: acknowledged while moves are queued, but not entered
            self.servo = bool(req.get("relFlag")) and not self.queue
        elif name == "is_in_servomove":
            reply["in_servomove"] = self.servo
        elif name in ("servo_j", "servo_p") and not self.servo:
            return copy.deepcopy(self.refusals["servo_j"])
        elif name == "torque_control_enable":
            self.drag = bool(req["enable_flag"])
        elif name == "get_drag_status":
            reply["status"] = self.drag
        elif name in ("set_tool_offsets", "set_user_offsets"):
            kind = name[4:8]
            offset = req["tooloffset" if kind == "tool" else "userffset"]
            self.offsets[kind][int(req["id"])] = [float(v) for v in offset]
        elif name in ("get_tool_offsets", "get_user_offsets"):
            kind = name[4:8]
            reply[f"{kind}_offsets"] = copy.deepcopy(self.offsets[kind])
        elif name in ("set_tool_id", "set_user_id"):
            kind = name[4:8]
            self.active[kind] = int(req["tool_id" if kind == "tool" else "user_frame_id"])
        elif name in ("get_curr_tool_id", "get_curr_user_id"):
            reply["id"] = self.active[name[9:13]]
        elif name in ("set_payload", "set_tio_vout_param"):
            self.settings[name.replace("set_", "get_")] = {
                k: v for k, v in req.items() if k != "cmdName"}
        elif name == "rapid_rate":
            self.settings["get_rapid_rate"] = {"value": float(req["rate_value"])}
        elif name in self.settings:
            reply.update(copy.deepcopy(self.settings[name]))
        elif name.startswith("set_") and name.endswith("_output"):
            kind = name[4:-7]   # digital / analog
            self.io[(kind + "_output", int(req["type"]), int(req["index"]))] = float(req["value"])
        elif name.startswith("get_") and ("_output" in name or "_input" in name):
            value = self.io.get((name[4:], int(req["type"]), int(req["index"])), 0)
            reply["value"] = int(value) if "digital" in name else float(value)
        return None

    def status_fields(self) -> Dict[str, Any]:
        with self.lock:
            self._advance()
            p = copy.deepcopy(self.packet)
            p["joint_actual_position"] = list(self.joints)
            if "joint_position" in p:       # the recorded fw 1.5.14 packet has none
                p["joint_position"] = list(self.joints)
            p["actual_position"] = p["position"] = list(self.tcp)
            p["inpos"] = not self.queue
            p["powered_on"], p["enabled"] = int(self.powered), self.enabled
            p["drag_status"] = self.drag
            p["current_tool_id"], p["current_user_id"] = self.active["tool"], self.active["user"]
            p["torqsensor"] = self.sensor.torqsensor(p["torqsensor"])
            for (kind, io_type, index), value in self.io.items():
                field = {"digital_output": "dout", "analog_output": "aout"}.get(kind)
                if field and io_type == 0:
                    p[field][index - 1] = int(value) if kind.startswith("digital") else value
        return p

    # ---- sockets -------------------------------------------------------------------------------
    def _serve(self, handler) -> int:
        """``handler(conn)`` for each connection to a new port on 127.0.0.1; the port."""
        server = TcpServer(handler, name="fake-controller", nodelay=False).start()
        self._servers.append(server)
        return server.port

    def _requests(self, conn: socket.socket):
        """Decoded requests from ``conn`` (compact JSON, no delimiter), until it closes."""
        decoder, buf = json.JSONDecoder(), ""
        conn.settimeout(0.1)
        while not self._quit.is_set():
            try:
                chunk = conn.recv(65536)
            except socket.timeout:
                continue
            except OSError:
                return
            if not chunk:
                return
            buf += chunk.decode()
            while buf.strip():
                buf = buf.lstrip()
                try:
                    obj, end = decoder.raw_decode(buf)
                except ValueError:
                    break
                with self.lock:
                    self.requests.append(obj)
                    self.texts.append(buf[:end])
                buf = buf[end:]
                yield obj

    def _command_client(self, conn: socket.socket) -> None:
        for req in self._requests(conn):
            if req.get("cmdName") == "wait_complete":
                while not self._quit.is_set():
                    with self.lock:
                        self._advance()
                        if not self.queue:
                            break
                    time.sleep(0.005)
            with self.lock:
                raw = self.raw_replies.pop(req.get("cmdName"), None)
            data = raw if raw is not None else json.dumps(self.answer(req),
                                                          separators=self.separators).encode()
            try:
                conn.sendall(data)
            except OSError:
                return

    def _status_client(self, conn: socket.socket) -> None:
        while not self._quit.wait(PERIOD):
            try:
                conn.sendall(encode_packet(self.status_fields()))
            except OSError:
                return

    def _data_client(self, conn: socket.socket) -> None:
        for req in self._requests(conn):
            if req.get("cmdName") == "data_request":
                try:
                    conn.sendall(zlib.compress(encode_packet(self.status_fields())))
                except OSError:
                    return


class FakeTorqueSensor:
    """The torque sensor's side of :class:`FakeController` (see its module)."""

    GETS = {"get_tool_payload": ("payload",), "get_torque_sensor_filter": ("filter",),
            "get_torque_sensor_soft_limit": ("soft_limit",),
            "get_admit_ctrl_config": ("admit",), "get_tool_drive_config": ("drive",),
            "get_compliant_type": ("compliant",), "get_ft_ctrl_frame": ("ft_frame",),
            "get_tool_drive_frame": ("drag_frame",), "get_tool_drive_stat": ("stat",)}

    def __init__(self):
        self.mode = 0
        self.values = {
            "payload": {"mass": 0.449, "centroid": [0, 0, 20]},     # the recorded packet's
            "filter": {"torqueSensorFilter": 0.0},
            "soft_limit": {"torqueSensorSoftLimit": {k: 0.0 for k in
                                                     ("Fx", "Fy", "Fz", "Mx", "My", "Mz")}},
            "admit": {"admitConfig": [[0, 0.0, 0.0, 0.0, 0] for _ in range(6)]},
            "drive": {"force_ctrl_config": [[0, 0.0, 0.0] for _ in range(6)]},
            "compliant": {"sensor_compensation": 0, "compliance_type": 0},
            "ft_frame": {"ftFrame": 0}, "drag_frame": {"toolDragFrame": 0},
            "stat": {"enable_flag": 0, "drive_stat": 0}}
        #: what the sensor reads (N, N·m), and whether the packet carries ``real`` as well
        self.actual = [0.0] * 6
        self.general = [0.0] * 6
        self.real = [0.0] * 6
        self.three_vectors = False
        #: sets acknowledged but not done (their get keeps the old value; mode: the packet)
        self.ignored: set = set()
        #: what get_torq_sensor_identify_staus answers next, one per poll (the last repeats)
        self.identify_statuses: List[int] = [0]
        self.identify_result = {"mass": 0.0, "centroid": [0.0, 0.0, 0.0]}

    def answer(self, name: str, req: Dict[str, Any]) -> Optional[Dict[str, Any]]:
        """The reply fields of a torque-sensor command (None: not one)."""
        if name in self.GETS:
            return copy.deepcopy(self.values[self.GETS[name][0]])
        fields = {k: v for k, v in req.items() if k != "cmdName"}
        if name in self.ignored:
            return {}
        if name == "set_torque_sensor_mode":
            self.mode = int(req["sensor_mode"])
        elif name == "set_tool_payload":
            self.values["payload"] = fields
        elif name in ("set_torque_sensor_filter", "set_torque_sensor_soft_limit",
                      "set_compliant_type", "set_ft_ctrl_frame", "set_tool_drive_frame"):
            key = {"set_torque_sensor_filter": "filter",
                   "set_torque_sensor_soft_limit": "soft_limit",
                   "set_compliant_type": "compliant", "set_ft_ctrl_frame": "ft_frame",
                   "set_tool_drive_frame": "drag_frame"}[name]
            self.values[key] = fields
        elif name == "set_admit_ctrl_config":
            self.values["admit"]["admitConfig"][int(req["axis"])] = [
                req["opt"], req["ftUser"], req["ftReboundFK"], req["ftConstant"],
                req["ftNnormalTrack"]]
        elif name == "set_tool_drive_config":
            self.values["drive"]["force_ctrl_config"][int(req["axis"])] = [
                req["opt"], req["rigidity"], req["rebound"]]
        elif name == "enable_admittance_ctrl":
            self.values["stat"]["enable_flag"] = int(req["enable_flag"])
        elif name == "disable_force_control":
            self.values["stat"]["enable_flag"] = 0
        elif name == "get_torq_sensor_identify_staus":
            status = self.identify_statuses[0]
            if len(self.identify_statuses) > 1:
                self.identify_statuses.pop(0)
            return {"identify_status": status}
        elif name == "get_torq_sensor_payload_identify_result":
            return dict(self.identify_result)
        elif name not in ("zero_end_sensor", "set_vel_compliant_ctrl",
                          "set_compliance_condition", "start_torq_sensor_payload_identify"):
            return None
        return {}

    def torqsensor(self, recorded: list) -> list:
        """The packet's torqsensor: the recorded one's settings with the sensor's payload,
        and ``[status, errcode, actual, general(, real)]`` (the errcode the packet has: a test
        may set it)."""
        config = copy.deepcopy(recorded[0])
        payload = self.values["payload"]
        config[2] = [payload["mass"], list(payload["centroid"])]
        vectors = [self.actual, self.general] + ([self.real] if self.three_vectors else [])
        return [config, [self.mode, recorded[1][1]] + [list(v) for v in vectors]]


@pytest.fixture
def fake():
    """A FakeController (moves take 0.3 s), closed after the test."""
    with FakeController(move_time=0.3) as controller:
        yield controller


@pytest.fixture
def backend(fake):
    """A ControllerBackend on ``fake``, shut down after the test."""
    b = start_backend(fake)
    yield b
    b.shutdown()


def start_backend(fake: "FakeController", model="zu5", source: str = "stream",
                  force_sensor: Optional[bool] = None):
    """A ControllerBackend connected to ``fake`` (status from ``source``; ``force_sensor``: the
    arm carries one), started."""
    from jaka_driver.controller import ControllerBackend
    from jaka_driver.common.models import load_model
    backend = ControllerBackend(load_model(model), "127.0.0.1", fake.command_port,
                                fake.status_port, status_source=source,
                                data_port=fake.data_port, call_timeout=2.0, stall_timeout=2.0,
                                force_sensor=force_sensor)
    backend.start()
    assert backend.link.connected, backend.link.down_message()
    return backend


def _closed_port() -> int:
    """A port number nobody listens on (connecting to it is refused)."""
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port
