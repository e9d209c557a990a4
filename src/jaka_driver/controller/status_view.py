"""From the controller's status stream to the driver's :class:`RobotState`.

What a packet carries is taken from it (docs/protocol.md, "Status packet"); the rest is derived:

* joint velocity, rad/s: the packet's ``instVel`` (deg/s on the wire). A controller that does
  not send it gets the finite difference of consecutive packets on their receipt times; packets
  that arrive in the same TCP read share one receipt time, so the difference is taken against
  the newest packet at least :data:`MIN_DT` older, which averages over such bursts instead of
  dividing by zero;
* joint effort, N·m: the joint torques of ``monitor_data``; zeros from a controller without it;
* joints and TCP: a packet whose positions are missing or unreadable keeps the last ones read
  (a made-up zero pose would look real);
* ``error_code``: the packet's ``errcode``; when that is 0, the torque sensor's error code
  (``torqsensor``), as JAKA's SDK reports it. The SDK also folds the soft limit, protective
  stop and emergency stop into its error code; here they stay flags of their own (a soft limit
  is not an error the arm must be cleared of: it is jogged out of);
* ``stamp``: receipt time (``time.time()``) of the packet — the stream has no time field;
  packets completed by one TCP read share it and make one sample, the last of them;
* the samples of the last :data:`HISTORY` packets are kept (:meth:`StatusView.states_since`),
  so a reader that fell behind (the node's publisher on a busy machine) still gets each one;
* servo mode: not in the stream; the backend's, from ``is_in_servomove``;
* IO: every array the packet carries (:func:`packet_io`: cabinet, tool, the extension module,
  relays, the fieldbus slaves), as it came;
* the program's state: not in the stream on record; the backend's programs facet's, read with
  ``get_program_state`` (:mod:`.programs`);
* ``force``: the force/torque sensor's readings of the same packet (``torqsensor``), made by
  :attr:`StatusView.force_reading` (the backend's force part when the arm carries a sensor:
  :func:`sensor_reading`), None otherwise;
* while the link is down the sample says so: ``connected`` False, not powered, not enabled, not
  moving (so ``motion_state`` reads Error and power 0), joints as last seen, stamped now.
"""
from __future__ import annotations

import math
import threading
import time
from collections import deque
from types import MappingProxyType
from typing import Callable, NamedTuple, Optional, Tuple

import numpy as np

from ..backend.force import GRAVITY, ForceReading, SensorPayload, gravity_wrench
from ..backend.robot_state import IoValues, RobotState
from ..common.transforms import pose_mm_rpy_to_matrix
from ..common.values import all_finite
from ..protocol.fields import FIELDBUS_SLAVES, IO_ARRAYS, IOType
from ..protocol.status_packet import StatusPacket

MIN_DT = 0.004   # s; packets closer than this in receipt time are one burst
HISTORY = 64     # samples kept for a reader that fell behind: 0.5 s of 8 ms packets


class _Packet(NamedTuple):
    """A packet as the view read it: what a sample of it is made from."""
    status: StatusPacket
    received: float            # s, time.time()
    q: np.ndarray              # rad, the last readable joints
    velocity: np.ndarray       # rad/s
    tcp: np.ndarray            # 4x4, m


def _finite(values: np.ndarray) -> bool:
    """No NaN or infinity among ``values`` (a packet's six): one sum in plain floats, cheaper
    than numpy's isfinite and all for six numbers (a sum of finite values that overflows
    counts as not finite: no joint or pose is near 1e308)."""
    return math.isfinite(sum(values.tolist()))


def is_collision(status: StatusPacket) -> bool:
    """JAKA reports a collision as a protective stop; only its message tells them apart (the
    emulator and real controllers both name it), so ``collision_state`` follows the text."""
    return status.protective_stop and "collision" in status.errmsg.lower()


#: an IO array's name → (signal, path) of the sample's IO (path 0 inputs, 1 outputs)
_ARRAY_KEY = {"din": ("digital", 0), "dout": ("digital", 1), "ain": ("analog", 0),
              "aout": ("analog", 1)}


def packet_io(status: StatusPacket) -> IoValues:
    """Every IO array ``status`` carries, keyed as a sample's IO is (signal, type, path): the
    cabinet's (``din`` … ``aout``), the tool's (``tio_*``), the extension module's (``extio``),
    the relays' (``relay_io``, outputs) and the fieldbus slaves' (``mb_slave_*``, ``pn_dev_*``,
    ``eip_adpt_*``). Arrays the packet does not carry, or carries empty, are absent."""
    io = {}

    def put(array: str, io_type: int, values) -> None:
        if values:
            signal, path = _ARRAY_KEY[array]
            io[(signal, int(io_type), path)] = tuple(values)
    for array in IO_ARRAYS:
        put(array, IOType.CABINET, getattr(status, array))
    put("din", IOType.TOOL, status.tio_din)
    put("dout", IOType.TOOL, status.tio_dout)
    put("ain", IOType.TOOL, status.tio_ain)
    for array, values in zip(IO_ARRAYS, status.extio):
        put(array, IOType.EXTEND, values)
    put("dout", IOType.RELAY, status.relay_io)
    for prefix, io_type in FIELDBUS_SLAVES:
        for array in IO_ARRAYS:
            put(array, io_type, status.fieldbus.get(f"{prefix}_{array}"))
    return MappingProxyType(io)


def sensor_reading(status: StatusPacket, flange_rotation: Callable[[], np.ndarray],
                   gravity: np.ndarray = GRAVITY) -> Optional[ForceReading]:
    """The packet's ``torqsensor`` as a :class:`ForceReading` (N, N·m, sensor frame): its
    ``actTorque``, ``torque`` and ``realTorque`` are ``actual``, ``general`` and ``real``, as
    JAKA's SDK reads them. None without the field, or while the sensor is off (``status`` 0).
    A packet without the third vector (the recorded Zu 5s sends two) gets ``real`` computed as
    the twin computes it: ``actual`` less the weight of the sensor's tool payload the same
    packet states, at the flange's orientation ``flange_rotation()`` (3x3, flange → base)
    under ``gravity`` (m/s², base frame: the arm's mounting, :attr:`StatusView.gravity`) — so ``~wrench_compensated`` means the same on every
    controller. A packet without ``actual`` has no reading."""
    ts = status.torque_sensor
    if ts is None or ts.status == 0 or not all_finite(ts.actual):
        return None
    real = ts.real
    if not all_finite(real):
        payload = SensorPayload(ts.payload_mass, np.asarray(ts.payload_centroid) / 1000.0)
        real = ts.actual - gravity_wrench(payload, flange_rotation(), gravity)
    return ForceReading(ts.actual, ts.general, real, ts.status, ts.errcode)


class StatusView:
    """The controller's latest status packet, what was read of the last :data:`HISTORY`, and
    the :class:`RobotState` made from one on request (:meth:`state`, :meth:`states_since`).

    :meth:`feed` is called from the status thread, everything else from any thread: :meth:`state`
    never blocks beyond a short lock and caches its answer until the next packet;
    :meth:`wait_for_packet` and :meth:`wait_until` sleep on a condition every packet notifies,
    so a waiter wakes the moment the packet it waits for exists.
    """

    def __init__(self):
        self._lock = threading.Lock()
        self._arrived = threading.Condition(self._lock)   # notified by every packet
        self._velocity = np.zeros(6)
        self._ref: Optional[tuple[float, np.ndarray]] = None   # (received, q) for the difference
        self._q = np.zeros(6)       # the last readable joints, rad
        self._tcp = np.eye(4)
        self._history: deque[_Packet] = deque(maxlen=HISTORY)   # the newest last
        #: (packet, servo_mode, program_state, its sample) of the newest packet's last sample
        self._cache: Optional[tuple[_Packet, bool, int, RobotState]] = None
        #: the sensor's readings in a packet, with the joints (rad) the view read from it
        self.force_reading: Callable[[StatusPacket, np.ndarray],
                                     Optional[ForceReading]] = lambda status, q: None
        #: m/s², base frame: gravity as the arm is mounted (read from the controller at every
        #: connection, :mod:`.mounting`); the sensor's compensated reading is computed under it
        self.gravity: np.ndarray = GRAVITY

    def reset(self) -> None:
        """A new connection: the next packet starts a new finite difference."""
        with self._lock:
            self._ref = None
            self._velocity = np.zeros(6)

    def feed(self, status: StatusPacket, received: float) -> None:
        """A packet received at ``received`` (s, ``time.time()``): :meth:`store`, then
        :meth:`announce`."""
        self.store(status, received)
        self.announce()

    def announce(self) -> None:
        """Wake whoever waits for a packet (:meth:`wait_for_packet`, :meth:`wait_until`).
        Separate from :meth:`store` so that the status thread wakes them last, right before
        it blocks on its socket again: a waiter woken earlier finds the interpreter lock still
        held and sleeps once more (two more thread switches per packet on a busy machine)."""
        with self._arrived:
            self._arrived.notify_all()

    def store(self, status: StatusPacket, received: float) -> None:
        """Keep ``status`` as the latest packet (its waiters are not woken: :meth:`announce`)."""
        q = status.joint_position
        reported = _finite(status.joint_velocity)     # instVel, else the difference
        tcp = pose_mm_rpy_to_matrix(status.tcp_pose) if _finite(status.tcp_pose) else None
        with self._lock:
            if _finite(q):
                self._q = q
                if self._ref is None:
                    self._ref = (received, q)
                elif received - self._ref[0] >= MIN_DT:
                    if not reported:
                        self._velocity = (q - self._ref[1]) / (received - self._ref[0])
                    self._ref = (received, q)
            if reported:
                self._velocity = status.joint_velocity
            if tcp is not None:
                self._tcp = tcp
            packet = _Packet(status, received, self._q, self._velocity, self._tcp)
            if self._history and self._history[-1].received == received:
                self._history[-1] = packet          # the same read: one sample, the last
            else:
                self._history.append(packet)

    def _newest(self) -> Optional[_Packet]:
        """The latest packet as read, None before the first (no lock needed: the history only
        grows, dropping its oldest)."""
        history = self._history
        return history[-1] if history else None

    @property
    def latest(self) -> Optional[StatusPacket]:
        """The latest packet, or None before the first."""
        newest = self._newest()
        return None if newest is None else newest.status

    @property
    def latest_received(self) -> Optional[Tuple[StatusPacket, float]]:
        """(latest packet, its receipt time s, ``time.time()``), or None before the first."""
        newest = self._newest()
        return None if newest is None else (newest.status, newest.received)

    def wait_for_packet(self, after: float, timeout: float) -> bool:
        """Block until a packet received later than ``after`` (s, ``time.time()``) is here, at
        most ``timeout`` s; True if one is."""
        with self._arrived:
            return self._arrived.wait_for(
                lambda: (newest := self._newest()) is not None and newest.received > after,
                timeout)

    def wait_until(self, shows: Callable[[StatusPacket], bool], timeout: float) -> bool:
        """Block until the latest packet satisfies ``shows`` (a quick test, called under the
        view's lock), at most ``timeout`` s; True if it does."""
        with self._arrived:
            return self._arrived.wait_for(
                lambda: (newest := self._newest()) is not None and shows(newest.status),
                timeout)

    def state(self, connected: bool, servo_mode: bool, program_state: int = 0) -> RobotState:
        """The sample of the latest packet (while the link is down: the last joints seen,
        stamped now); ``servo_mode`` and ``program_state`` are the backend's."""
        with self._lock:
            latest = self._newest()
            q, tcp = self._q, self._tcp
        if latest is None:
            return RobotState(stamp=time.time(), connected=False,
                              error_message="no status received from the controller yet")
        if not connected:
            return RobotState(stamp=time.time(), joint_position=q, tcp_pose=tcp,
                              tool_id=latest.status.current_tool_id,
                              user_id=latest.status.current_user_id,
                              connected=False, error_message="connection to the controller lost")
        return self._sample(latest, servo_mode, program_state)

    def states_since(self, after: float, connected: bool, servo_mode: bool,
                     program_state: int = 0) -> list[RobotState]:
        """The samples of the kept packets received later than ``after`` (s, ``time.time()``),
        oldest first: a reader that fell behind gets every one of the last :data:`HISTORY`.
        While the link is down: :meth:`state`, if it is newer."""
        if not connected:
            st = self.state(connected, servo_mode, program_state)
            return [st] if st.stamp > after else []
        with self._lock:
            newer = []
            for packet in reversed(self._history):         # usually one is new
                if packet.received <= after:
                    break
                newer.append(packet)
        return [self._sample(p, servo_mode, program_state) for p in reversed(newer)]

    def _sample(self, packet: _Packet, servo_mode: bool, program_state: int) -> RobotState:
        """The connected sample of ``packet``; the latest one's is made once and cached."""
        cache = self._cache
        if cache is not None and cache[0] is packet and cache[1:3] == (servo_mode, program_state):
            return cache[3]
        status = packet.status
        effort = status.joint_torque if all_finite(status.joint_torque) \
            else np.zeros(6)
        st = RobotState(
            stamp=packet.received, joint_position=packet.q, joint_velocity=packet.velocity,
            joint_effort=effort, tcp_pose=packet.tcp, tool_id=status.current_tool_id,
            user_id=status.current_user_id, connected=True, powered=status.powered,
            enabled=status.enabled, servo_mode=servo_mode, drag_mode=status.drag_status,
            emergency_stop=status.emergency_stop, protective_stop=status.protective_stop,
            collision=is_collision(status), moving=not status.inpos,
            error_code=status.errcode or status.sensor_errcode,
            error_message=status.errmsg if status.errcode or not status.sensor_errcode
            else f"torque sensor error {status.sensor_errcode}", program_state=program_state,
            io=packet_io(status), force=self.force_reading(status, packet.q),
            on_limit=bool(status.on_soft_limit))
        with self._lock:
            if packet is self._newest():                # only the latest is worth keeping
                self._cache = (packet, servo_mode, program_state, st)
        return st
