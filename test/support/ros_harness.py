"""Real parts for integration tests: a rosmaster on a free port, the driver node as a
subprocess, service calls and topic capture. Every process started here is stopped here."""
from __future__ import annotations

import os
import random
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]     # the repository
NODE = ROOT / "scripts" / "jaka_driver_node"


#: First port of the blocks free_port draws from, below the kernel's ephemeral range (32768 and
#: up on Linux), where bind(0) and outgoing connections take theirs
PORT_BLOCKS = 20000
PORT_BLOCK = 1000
_handed_out: set = set()


def free_port() -> int:
    """A TCP port of 127.0.0.1 that nobody listens on, for a server this test starts by port
    number (rosmaster, an emulator restarted on the same ports). Each of pytest-xdist's worker
    processes draws from its own block (``gw<N>``: 20000 + 1000·N …), at random within it and
    never the same port twice, so no other worker can pick it before its server binds it (with
    bind(0) it could: the kernel hands a released port to the next caller)."""
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0")
    block = PORT_BLOCKS + PORT_BLOCK * (int(worker[2:] or 0) % 12)
    pick = random.SystemRandom()
    for _ in range(200):
        port = pick.randrange(block, block + PORT_BLOCK)
        if port in _handed_out:
            continue
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
        _handed_out.add(port)
        return port
    raise RuntimeError(f"no free port in {block}..{block + PORT_BLOCK - 1}")


def wait_until(predicate, timeout: float, period: float = 0.02):
    """Poll ``predicate`` until it returns a truthy value or ``timeout`` s pass."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value or time.monotonic() > deadline:
            return value
        time.sleep(period)


class RosMaster:
    """``rosmaster --core`` on a free port, with ROS_* variables pointing at it."""

    def __init__(self):
        self.home = tempfile.mkdtemp(prefix="jaka_ros_home_")
        for attempt in range(3):       # a port taken between its pick and the bind: another
            self.port = free_port()
            self.uri = f"http://localhost:{self.port}/"
            self.proc = subprocess.Popen(["rosmaster", "--core", "-p", str(self.port)],
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                         start_new_session=True)
            proxy = xmlrpc.client.ServerProxy(self.uri)

            def up():
                try:
                    proxy.getSystemState("/test")
                    return True
                except OSError:
                    return self.proc.poll() is not None      # exited: stop waiting

            if wait_until(up, 15.0, 0.05) and self.proc.poll() is None:
                break
            self.stop()
        else:
            raise RuntimeError("rosmaster did not come up in 15 s")
        os.environ.update(ROS_MASTER_URI=self.uri, ROS_HOSTNAME="localhost",
                          ROS_HOME=self.home, ROS_LOG_DIR=os.path.join(self.home, "log"))
        os.environ.pop("ROS_IP", None)

    def stop(self):
        stop_process(self.proc)


def stop_process(proc: subprocess.Popen, timeout: float = 10.0) -> None:
    """SIGINT (clean ROS shutdown), then SIGKILL the whole process group."""
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, signal.SIGINT)
            proc.wait(timeout=timeout)
        except (subprocess.TimeoutExpired, ProcessLookupError):
            pass
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait()


def descendants(pid: int) -> list[int]:
    """Every live descendant of ``pid``: roslaunch starts each node in a session of its own,
    so signalling its process group does not reach them."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    # the command name may hold spaces: the ppid follows its closing bracket
                    parents[int(entry)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    found, frontier = [], [pid]
    while frontier:
        p = frontier.pop()
        kids = [c for c, pp in parents.items() if pp == p]
        found += kids
        frontier += kids
    return found


def stop_launch(proc: subprocess.Popen, timeout: float = 20.0) -> None:
    """SIGINT lets roslaunch stop its nodes; whatever it started and is still alive after
    ``timeout`` s is killed by pid."""
    started = descendants(proc.pid)
    stop_process(proc, timeout)
    for pid in started:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()


class LaunchProcess:
    """``roslaunch jaka_driver jaka_driver.launch <arg>:=<value> …`` on the test's master, its
    output (the driver's, ``output="screen"``) in a log file."""

    def __init__(self, log_name: str = "launch", **args):
        self.prefix = "/jaka_driver"
        log_dir = Path(os.environ.get("ROS_LOG_DIR", tempfile.gettempdir()))
        self.log_path = log_dir / f"{log_name}.log"
        self.log_path.parent.mkdir(parents=True, exist_ok=True)
        self._log = open(self.log_path, "wb")
        self.proc = subprocess.Popen(
            ["roslaunch", "jaka_driver", "jaka_driver.launch"]
            + [f"{k}:={v}" for k, v in args.items()],
            stdout=self._log, stderr=subprocess.STDOUT, start_new_session=True,
            env=os.environ.copy())

    def name(self, leaf: str) -> str:
        return f"{self.prefix}/{leaf}"

    def wait_ready(self, timeout: float = 60.0) -> None:
        """Until the driver has said "jaka_driver ready"."""
        ready = wait_until(lambda: "jaka_driver ready" in self.log_path.read_text(errors="replace")
                           or self.proc.poll() is not None, timeout, 0.05)
        if not ready or self.proc.poll() is not None:
            raise RuntimeError(f"roslaunch not ready in {timeout} s; log:\n{self.log()}")

    def log(self) -> str:
        self._log.flush()
        return self.log_path.read_text(errors="replace")[-4000:]

    def stop(self) -> None:
        stop_launch(self.proc)
        self._log.close()


def forget_params(prefix: str) -> None:
    """Remove the params under ``prefix`` (a node's private namespace) from the master.
    Private params stay on the master after a node exits (a previous module's ``_scene:=...``
    or ``_sim_time:=true`` would reach the next node of that name): a node started after this
    starts from a clean slate, as under a fresh roslaunch."""
    try:
        xmlrpc.client.ServerProxy(os.environ["ROS_MASTER_URI"]).deleteParam("/test_harness",
                                                                            prefix)
    except xmlrpc.client.Fault:
        pass


class DriverProcess:
    """The real node, started as ``rosrun`` would, with private params ``_name:=value``."""

    def __init__(self, ns: str = "", log_name: str = "driver", **params):
        args = [str(NODE)] + [f"_{k}:={v}" for k, v in params.items()]
        if ns:
            args.append(f"__ns:={ns}")
        self.ns = ns
        self.prefix = f"/{ns}/jaka_driver" if ns else "/jaka_driver"
        forget_params(self.prefix)
        self.log_path = Path(os.environ.get("ROS_LOG_DIR", tempfile.gettempdir())) / f"{log_name}.log"
        self.log_path.parent.mkdir(parents=True, exist_ok=True)
        self._log = open(self.log_path, "wb")
        self.proc = subprocess.Popen(args, stdout=self._log, stderr=subprocess.STDOUT,
                                     start_new_session=True, env=os.environ.copy())

    def name(self, leaf: str) -> str:
        return f"{self.prefix}/{leaf}"

    def wait_ready(self, timeout: float = 60.0) -> None:
        """Until the node has said "jaka_driver ready" (logged once every service, the action
        server, TF and diagnostics are up): a service answering is not enough, the node
        advertises them one after the other."""
        import rospy
        end = time.monotonic() + timeout
        try:
            rospy.wait_for_service(self.name("clear_err"), timeout=timeout)
        except rospy.ROSException:
            raise RuntimeError(f"driver not ready in {timeout} s; log:\n{self.log()}") from None
        while "jaka_driver ready" not in self.log_path.read_text(errors="replace"):
            if time.monotonic() > end or not self.alive():
                raise RuntimeError(f"driver not ready in {timeout} s; log:\n{self.log()}")
            time.sleep(0.05)

    def log(self) -> str:
        self._log.flush()
        return self.log_path.read_text(errors="replace")[-4000:]

    def alive(self) -> bool:
        return self.proc.poll() is None

    def stop(self) -> None:
        stop_process(self.proc)
        self._log.close()


class Services:
    """Persistent proxies to the driver's services, created on first use."""

    def __init__(self, driver: DriverProcess):
        self._driver = driver
        self._proxies = {}

    def __call__(self, leaf: str, srv_type, *args, **fields):
        import rospy
        proxy = self._proxies.get(leaf)
        if proxy is None:
            proxy = rospy.ServiceProxy(self._driver.name(leaf), srv_type, persistent=True)
            self._proxies[leaf] = proxy
        try:
            return proxy(*args, **fields)
        except (rospy.ServiceException, OSError):
            # a persistent connection does not survive everything; retry once fresh
            proxy.close()
            proxy = rospy.ServiceProxy(self._driver.name(leaf), srv_type, persistent=True)
            self._proxies[leaf] = proxy
            return proxy(*args, **fields)

    def close(self):
        for proxy in self._proxies.values():
            proxy.close()


def delivers_to_us(driver, leaf: str) -> bool:
    """True once the node ``driver`` has this test process among the subscribers of its topic
    ``leaf`` (its own bus info, ``rosnode info``'s source). A subscriber counts its connection
    when the node's header has reached it; the node adds it to its publisher a moment later,
    and a message published in between goes to no one."""
    import rosgraph
    import rospy
    me = rospy.get_name()
    topic = driver.name(leaf)
    try:
        api = rosgraph.Master(me).lookupNode(driver.prefix)
        _, _, info = xmlrpc.client.ServerProxy(api).getBusInfo(me)
    except (OSError, rosgraph.MasterError, xmlrpc.client.Error):
        return False
    return any(c[4] == topic and c[1] == me and c[2] == "o" for c in info)


class Recorder:
    """Subscribes to a topic and keeps (receipt time, message) pairs."""

    def __init__(self, topic: str, msg_type, keep: int = 100000):
        import rospy
        self._lock = threading.Lock()
        self.samples: list = []
        self._keep = keep
        self._sub = rospy.Subscriber(topic, msg_type, self._on, queue_size=1000,
                                     tcp_nodelay=True)

    def _on(self, msg):
        with self._lock:
            self.samples.append((time.time(), msg))
            if len(self.samples) > self._keep:
                del self.samples[: len(self.samples) - self._keep]

    def latest(self):
        with self._lock:
            return self.samples[-1][1] if self.samples else None

    def since(self, t0: float) -> list:
        with self._lock:
            return [(t, m) for t, m in self.samples if t >= t0]

    def clear(self):
        with self._lock:
            self.samples.clear()

    def close(self):
        self._sub.unregister()


# --- the arm: a test's clean slate and reading where it stands ---

#: JAKA's "pose_1": upper arm up, forearm forward, flange down — the twin's start pose (rad)
START = [0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0]
#: s, the twin's (and a JAKA controller's) cycle
CYCLE = 0.008



def start_driver(request, **params):
    driver = DriverProcess(log_name=request.module.__name__, **params)
    request.addfinalizer(driver.stop)
    driver.wait_ready()
    return driver


def go_home(call) -> None:
    """Leave servo mode, stop whatever moves and return to START (a test's clean slate)."""
    from jaka_msgs.srv import Move, ServoMoveEnable
    from std_srvs.srv import Empty
    call("servo_move_enable", ServoMoveEnable, enable=False)
    call("stop_move", Empty)
    reply = wait_until(lambda: (r := call("joint_move", Move, pose=START, mvvelo=2.0,
                                          mvacc=8.0)).ret == 1 and r, 3.0, 0.2)
    assert reply, "could not return to START"


def position(recorder, timeout=5.0) -> np.ndarray:
    """Joint position (rad) as of now, from a JointState recorder: a message stamped
    at or after this call (ROS time), not merely the latest received — a subscriber that a
    busy machine holds up can be tens of ms behind, and a test that checks where a blocking
    move left the arm must not read a sample from before its reply."""
    import rospy
    now = rospy.get_rostime().to_sec()

    def current():
        with recorder._lock:
            return next((m for _, m in reversed(recorder.samples) if stamp(m) >= now), None)

    msg = wait_until(current, timeout)
    assert msg is not None, f"no joint_position message stamped after {now:.3f} within {timeout} s"
    return np.array(msg.position)


def moving_span(recorder, after: float, until: float = float("inf"),
                speed: float = 1e-3) -> tuple:
    """(first, last) stamp (s) of the samples stamped in [``after``, ``until``] in which a joint
    moves faster than ``speed`` rad/s: a motion's duration as the arm's own samples tell it
    (the twin's 8 ms cycles; a controller's status packets, stamped on arrival), without the
    time a test's call and its answer take on a busy machine's wall clock."""
    with recorder._lock:
        moved = [stamp(m) for _, m in recorder.samples
                 if after <= stamp(m) <= until and np.max(np.abs(m.velocity)) > speed]
    assert moved, f"no sample moving faster than {speed:g} rad/s after {after:.3f} s"
    return moved[0], moved[-1]


def moving_cycles(recorder, after: float, until: float = float("inf"),
                  speed: float = 1e-3) -> int:
    """How many samples stamped in [``after``, ``until``] show a joint moving faster than
    ``speed`` rad/s: on the twin, the 8 ms cycles a motion took. Where the stamps' span
    (:func:`moving_span`) can only be longer than the motion (a twin that stalled for more than
    STALL_CYCLES skips its stamps ahead), the count can only be shorter (a sample its publisher
    had to drop is missing), so together they bound the motion from both sides."""
    with recorder._lock:
        return len({stamp(m) for _, m in recorder.samples
                    if after <= stamp(m) <= until and np.max(np.abs(m.velocity)) > speed})


def at_rest(recorder, timeout=3.0, speed=1e-3) -> np.ndarray:
    """Joint position once every joint is slower than ``speed`` rad/s (the end of a move's
    settling), so a later comparison sees only new motion."""
    msg = wait_until(lambda: (m := recorder.latest()) is not None
                     and np.max(np.abs(m.velocity)) < speed and m, timeout)
    assert msg, "the arm did not come to rest"
    return np.array(msg.position)


# --- simulated time: the twin owns time (sim_time); the tests read it from the samples ---

def forget_sim_time() -> None:
    """Remove /use_sim_time, so the next node starts on the wall clock."""
    xmlrpc.client.ServerProxy(os.environ["ROS_MASTER_URI"]).deleteParam("/test_harness",
                                                                        "/use_sim_time")


def start_sim_time_driver(request, real_time_factor=0, **params):
    """The node on the zu5 twin with ``sim_time``: /use_sim_time is removed again when it
    stops, so the next module's driver starts on the wall clock."""
    request.addfinalizer(forget_sim_time)
    return start_driver(request, backend="sim", model="zu5", sim_time="true",
                        real_time_factor=real_time_factor, **params)


def pause_twin(call, pause: bool = True) -> None:
    """Stop (``pause``) or run on the twin's simulated time (``~sim/pause``)."""
    from jaka_driver_msgs.srv import PauseTwin
    reply = call("sim/pause", PauseTwin, pause=pause)
    assert reply.ret == 1, reply.message


def step_twin(call, cycles: int) -> float:
    """Run the paused twin ``cycles`` 8 ms cycles (``~sim/step``); the sim time (s) after them.
    Every sample of those cycles is published (the twin waits for its publisher), and a
    subscriber has at most those to catch up on: none piles up while the twin stands still."""
    from jaka_driver_msgs.srv import StepTwin
    reply = call("sim/step", StepTwin, cycles=int(cycles))
    assert reply.ret == 1, reply.message
    return reply.sim_time


def step_twin_to(call, t: float) -> float:
    """Step the paused twin until its sim time is at least ``t`` (s); the sim time after."""
    now = step_twin(call, 1)
    cycles = int(np.ceil((t - now) / CYCLE - 1e-6))
    return step_twin(call, cycles) if cycles > 0 else now


def reset_twin(call, joints) -> float:
    """The paused twin at a fresh start at rest at ``joints`` (rad, ``~sim/reset``: no motion,
    no jog, no servo stream), then one cycle stepped: its sim time (s), the stamp of the first
    sample of the arm at rest there, is returned."""
    from jaka_driver_msgs.srv import ResetTwin
    reply = call("sim/reset", ResetTwin, joints=list(joints))
    assert reply.ret == 1, reply.message
    return step_twin(call, 1)


def stamp(msg) -> float:
    return msg.header.stamp.to_sec()


def sample_at(recorder, t: float, timeout: float = 30.0):
    """The first message stamped at or after ``t`` (s, sim time), waiting for it. The wait is
    long in wall time: the twin waits for its publisher, which waits for slow subscribers, so on
    a machine two busy processes fill, sim time can crawl at the pace the test reads."""
    def find():
        with recorder._lock:
            return next((m for _, m in recorder.samples if stamp(m) >= t - 1e-6), None)

    msg = wait_until(find, timeout, 0.005)
    assert msg is not None, f"no sample stamped {t:.3f} s within {timeout} s of wall time"
    return msg


def sim_sleep(recorder, seconds: float):
    """Wait ``seconds`` of the twin's time, counted from the latest sample; returns the
    sample that ends the wait."""
    latest = wait_until(recorder.latest, 5.0)
    assert latest is not None, "no sample"
    return sample_at(recorder, stamp(latest) + seconds)


# --- actions ---

def action_done(client, timeout: float) -> bool:
    """Whether the goal a ``SimpleActionClient`` sent last is done (its result in) within
    ``timeout`` s of wall time, read from the goal's own handle.

    Not ``wait_for_result``: SimpleActionClient takes the handle of a goal only once
    ``send_goal`` has returned, and an answer that comes before that — a refusal, at once, on a
    busy machine — updates the handle but never the client's simple state ("a transition
    callback on a goal handle that we're not tracking", ros/actionlib#206), so it waits out its
    whole timeout. Nor ROS time: in sim time this process's clock is the last /clock it read."""
    import actionlib
    return bool(wait_until(lambda: client.gh is not None
                           and client.gh.get_comm_state() == actionlib.CommState.DONE,
                           timeout, 0.005))
