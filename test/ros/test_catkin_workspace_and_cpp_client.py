"""A catkin user's day: the repository in a fresh workspace's src/, `catkin_make`, the node run
from the devel space and driven by a roscpp client (test/cpp) built in the same workspace
against the jaka_msgs C++ headers, JAKA's servoj_demo pattern with `servo_increment:=true`,
the calls of JAKA's two example programs (client.cpp, servoj_demo.cpp: written anew from the
facts in test/cpp/jaka_driver_cpp_client/README.md) and a PoseStamped tool_position subscriber
with `conventions:=jaka_code`, then `catkin_make install` and the node run from the install space, finding its URDF in
share/ and the IK library in lib/.

The commands are docs/catkin.md's ("Using with a catkin workspace", "C++ clients"), run as a shell
would, in an environment without this repository's devel/setup.bash (no JAKA_DRIVER_ROOT, no
generated messages on PYTHONPATH). One workspace build is shared by the module (~25 s on two
cores, the C++ client being most of it).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import time
from pathlib import Path

import math

import numpy as np
import pytest

from support.ros_harness import ROOT, forget_params, forget_sim_time, stop_process, wait_until

pytestmark = pytest.mark.ros

CATKIN_DOC = ROOT / "docs" / "catkin.md"
# Exactly as docs/catkin.md shows them (test_catkin_doc_shows_the_commands).
CATKIN_MAKE = "catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3"
CATKIN_INSTALL = "catkin_make install -DPYTHON_EXECUTABLE=/usr/bin/python3"
RUN_NODE = "rosrun jaka_driver jaka_driver_node"
RUN_NODE_INCREMENTS = "rosrun jaka_driver jaka_driver_node _servo_increment:=true"
RUN_NODE_JAKA_CODE = "rosrun jaka_driver jaka_driver_node _conventions:=jaka_code"
CPP_DEPENDS = "find_package(catkin REQUIRED COMPONENTS roscpp jaka_msgs)"
DOC_LINES = [CATKIN_MAKE, CATKIN_INSTALL, "source devel/setup.bash", "source install/setup.bash",
                RUN_NODE_INCREMENTS, RUN_NODE_JAKA_CODE, CPP_DEPENDS,
                "<depend>jaka_driver</depend>"]
POSE = [0.5, 1.9, -1.4, 1.1, 1.57, 0.0]
TCP_MM_ROTVEC = [209.5, 244.3, 600.1, -2.681, 1.590, -0.024]


def _clean_env() -> dict:
    """The test run's environment less what this repository's devel/setup.bash added."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "JAKA_DRIVER_ROOT", "CMAKE_PREFIX_PATH", "ROS_PACKAGE_PATH",
                        "JAKA_IK_LIB", "JAKA_DRIVER_NO_REEXEC", "VIRTUAL_ENV")}
    venv_bin = str(ROOT / ".venv" / "bin")
    env["PATH"] = ":".join(p for p in env["PATH"].split(":")
                           if p and Path(p).resolve() != Path(venv_bin).resolve())
    env["ROS_PARALLEL_JOBS"] = "-j2"        # a shared two-core machine
    env["PYTHONUNBUFFERED"] = "1"           # the node's log lines reach its log file at once
    return env


def _sourced(env: dict, setup: Path) -> dict:
    out = subprocess.run(["bash", "-c", f"source {setup} && env -0"], env=env, check=True,
                         capture_output=True)
    return dict(line.split("=", 1) for line in out.stdout.decode().split("\0") if "=" in line)


def _shell(command: str, cwd: Path, env: dict, timeout: float = 600):
    out = subprocess.run(["nice", "-n", "10", "bash", "-c", command], cwd=cwd, env=env,
                         capture_output=True, text=True, timeout=timeout)
    assert out.returncode == 0, f"{command} failed:\n{out.stdout[-4000:]}\n{out.stderr[-4000:]}"
    return out


def _copy_repository(dest: Path) -> None:
    """What a clone holds: the tracked files (and new ones not ignored yet), without .venv."""
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard"], cwd=ROOT,
                           check=True, capture_output=True, text=True).stdout.split("\n")
    for name in filter(None, files):
        src = ROOT / name
        if name == ".venv" or not src.is_file():
            continue
        (dest / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, dest / name)
    # The venv is ~600 MB of pip packages: share the one `make setup` made (scripts/setup.sh
    # --deps, run by the CMake, then finds it up to date).
    (dest / ".venv").symlink_to((ROOT / ".venv").resolve())


@pytest.fixture(scope="module")
def workspace(tmp_path_factory, ros_master):
    ws = tmp_path_factory.mktemp("catkin_ws")
    _copy_repository(ws / "src" / "jaka_driver")
    shutil.copytree(ROOT / "test" / "cpp" / "jaka_driver_cpp_client",
                    ws / "src" / "jaka_driver_cpp_client")
    t0 = time.monotonic()
    _shell(CATKIN_MAKE, ws, _clean_env())
    print(f"catkin_make: {time.monotonic() - t0:.1f} s")
    return ws


class Node:
    """The node started with rosrun from a sourced workspace; its output in a log file."""

    def __init__(self, command: str, env: dict, log: Path):
        # what an earlier module's node left on this worker's master (~sim_time, ~scene, ...)
        # would reach this one: it starts as on a fresh master
        forget_params("/jaka_driver")
        forget_sim_time()
        self.log_path = log
        self._log = open(log, "wb")
        self.proc = subprocess.Popen(["bash", "-c", f"exec {command}"], env=env,
                                     stdout=self._log, stderr=subprocess.STDOUT,
                                     start_new_session=True)
        ready = wait_until(lambda: "jaka_driver ready" in self.log() or self.proc.poll() is not None,
                           90.0, 0.1)
        if not ready or self.proc.poll() is not None:
            self.stop()
            raise AssertionError(f"{command}: not ready in 90 s\n{self.log()}")

    def log(self) -> str:
        return self.log_path.read_text(errors="replace")

    def stop(self):
        stop_process(self.proc)
        self._log.close()


def _client(ws: Path, env: dict, mode: str) -> dict:
    out = subprocess.run([str(ws / "devel" / "lib" / "jaka_driver_cpp_client" / "jaka_cpp_client"),
                          mode], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and "OK" in out.stdout, f"{out.stdout}\n{out.stderr}"
    return {line.split()[0]: np.array([float(v) for v in line.split()[1:]])
            for line in out.stdout.splitlines() if line and not line.startswith(("OK", "\x1b"))}


def test_devel_space_has_jaka_msgs_for_cpp_python_and_rosmsg(workspace):
    devel = workspace / "devel"
    assert (devel / "include" / "jaka_msgs" / "Move.h").is_file()
    assert (devel / "include" / "jaka_msgs" / "RobotMsg.h").is_file()
    assert (devel / "share" / "jaka_msgs" / "cmake" / "jaka_msgsConfig.cmake").is_file()
    env = _sourced(_clean_env(), devel / "setup.bash")
    msg = _shell("rosmsg show jaka_msgs/RobotMsg", workspace, env).stdout
    assert "int16 servo_state" in msg and "int16 collision_state" in msg
    srv = _shell("rossrv show jaka_msgs/Move", workspace, env).stdout
    assert "float32[] pose" in srv and "int16 ret" in srv
    md5 = _shell("/usr/bin/python3 -c 'import jaka_msgs.srv as s; print(s.Move._md5sum)'",
                 workspace, env).stdout.strip()
    from jaka_msgs.srv import Move          # this repository's own generation
    assert md5 == Move._md5sum


def test_cpp_client_drives_the_node_run_from_the_devel_space(workspace, tmp_path):
    env = _sourced(_clean_env(), workspace / "devel" / "setup.bash")
    node = Node(RUN_NODE, env, tmp_path / "node.log")
    try:
        got = _client(workspace, env, "services")
        log = node.log()
    finally:
        node.stop()
    # found through the workspace's package and devel space, not this repository's tree
    assert f"URDF {workspace}/src/jaka_driver/urdf/jaka_zu5.urdf" in log
    assert f"IK library {workspace}/devel/lib/libjaka_ik.so" in log
    assert got["joint_move_arrived"] == pytest.approx(POSE, abs=2e-3)
    assert got["get_fk"] == pytest.approx(TCP_MM_ROTVEC, abs=0.1)
    down = np.array(TCP_MM_ROTVEC) - [0, 0, 50, 0, 0, 0]
    assert got["linear_move_arrived_tcp"] == pytest.approx(down, abs=0.5)
    assert got["get_ik"] == pytest.approx(got["servo_j_start"], abs=2e-3)
    assert got["get_io"][0] == 1.0
    assert got["servo_state_in_servo_mode"][0] == 1.0
    moved = got["servo_j_end"] - got["servo_j_start"]
    assert moved == pytest.approx([0, 0, 0, 0, 0, 0.05], abs=2e-3)
    # per second of the samples' stamps (the twin's cycles; a gap longer than its stall window,
    # time a busy machine made it skip, counts as one cycle): every sample published once
    assert got["topic_rates_hz"] == pytest.approx([125, 125], abs=10)


def test_servoj_demo_increments_move_the_arm_with_servo_increment(workspace, tmp_path):
    """JAKA's servoj_demo: 200 calls of {0.001, 0, 0, 0, 0, 0.001} → J1 and J6 +0.2 rad."""
    env = _sourced(_clean_env(), workspace / "devel" / "setup.bash")
    node = Node(RUN_NODE_INCREMENTS, env, tmp_path / "node.log")
    try:
        got = _client(workspace, env, "increments")
    finally:
        node.stop()
    moved = got["increments_end"] - got["increments_start"]
    assert moved == pytest.approx([0.2, 0, 0, 0, 0, 0.2], abs=2e-3)


# JAKA's example client, from the README's facts: the pose is [atof(argv[0]) = 0, arg1..arg5];
# the sixth argument is never read.
EXAMPLE_ARGS = ["-460", "350", str(math.pi), "0", str(-math.pi / 2), "999"]
EXAMPLE_POSE_MM = [0.0, -460.0, 350.0]                # mm
EXAMPLE_RPY = [math.pi, 0.0, -math.pi / 2]            # rad, R = Rz·Ry·Rx
EXAMPLE_START = [-1.2, 1.57, -1.57, 1.57, 1.57, 0.0]   # rad, a joint_move before the example


def _quaternion_from_rpy(rx, ry, rz):
    """(x, y, z, w) of R = Rz(rz)·Ry(ry)·Rx(rx), as tf2's setRPY writes it."""
    cr, sr, cp, sp, cy, sy = (math.cos(rx / 2), math.sin(rx / 2), math.cos(ry / 2),
                              math.sin(ry / 2), math.cos(rz / 2), math.sin(rz / 2))
    return np.array([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy])


def _program(ws: Path, env: dict, name: str, *args: str) -> str:
    out = subprocess.run([str(ws / "devel" / "lib" / "jaka_driver_cpp_client" / name), *args],
                         env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, f"{name}: {out.stdout}\n{out.stderr}"
    return out.stdout


def _tool_position(ws: Path, env: dict):
    """(position mm, quaternion, frame_id) from the PoseStamped subscriber."""
    line = next(l for l in _program(ws, env, "jaka_pose_stamped_listener").splitlines()
                if l.startswith("tool_position"))
    fields = line.split()
    return np.array([float(v) for v in fields[1:4]]), np.array([float(v) for v in fields[4:8]]), \
        fields[8]


def test_jakas_example_programs_reach_their_poses_in_jaka_code_mode(workspace, tmp_path,
                                                                   rospy_node):
    """client.cpp's linear_move (RPY) and servoj_demo's 200 increments, as their calls are
    recorded in test/cpp/jaka_driver_cpp_client/README.md, reach the poses they would reach on
    JAKA's driver; a subscriber written for JAKA's PoseStamped tool_position reads them in
    mm."""
    import rospy
    from jaka_msgs.srv import Move
    from sensor_msgs.msg import JointState
    env = _sourced(_clean_env(), workspace / "devel" / "setup.bash")
    node = Node(RUN_NODE_JAKA_CODE, env, tmp_path / "node.log")
    try:
        log = node.log()
        assert rospy.ServiceProxy("/jaka_driver/joint_move", Move)(
            pose=EXAMPLE_START, mvvelo=1.5, mvacc=4.0).ret == 1
        printed = _program(workspace, env, "jaka_example_linear_move", *EXAMPLE_ARGS)
        assert "ret 1" in printed, printed
        position, quaternion, frame = _tool_position(workspace, env)
        before = np.array(rospy.wait_for_message("/jaka_driver/joint_position", JointState,
                                                 5.0).position)
        printed = _program(workspace, env, "jaka_example_servoj_demo")
        after = np.array(rospy.wait_for_message("/jaka_driver/joint_position", JointState,
                                                5.0).position)
    finally:
        node.stop()
        # rosrun's _conventions:=... stays on the parameter server for the next node
        rospy.delete_param("/jaka_driver/conventions")
    assert "conventions jaka_code" in log
    assert position == pytest.approx(EXAMPLE_POSE_MM, abs=1.0)      # mm, not m
    expected = _quaternion_from_rpy(*EXAMPLE_RPY)
    assert min(np.abs(quaternion - expected).max(), np.abs(quaternion + expected).max()) < 2e-3
    assert frame == "base_link"
    assert printed.count("servo_j ret 1") == 200, printed[-2000:]
    assert after - before == pytest.approx([0.2, 0, 0, 0, 0, 0.2], abs=2e-3)


def test_install_space_node_finds_urdf_in_share_and_ik_in_lib(workspace, tmp_path, rospy_node):
    _shell(CATKIN_INSTALL, workspace, _clean_env())
    install = workspace / "install"
    for path in ["include/jaka_msgs/Move.h", "share/jaka_msgs/cmake/jaka_msgsConfig.cmake",
                 "share/jaka_msgs/package.xml", "lib/libjaka_ik.so",
                 "lib/python3/dist-packages/jaka_msgs/srv/_Move.py",
                 "share/jaka_driver/urdf/jaka_zu5.urdf", "lib/jaka_driver/jaka_driver_node"]:
        assert (install / path).exists(), path
    env = _sourced(_clean_env(), install / "setup.bash")
    assert "int16 servo_state" in _shell("rosmsg show jaka_msgs/RobotMsg", workspace, env).stdout
    node = Node(RUN_NODE, env, tmp_path / "node.log")
    try:
        log = node.log()
        from jaka_msgs.srv import GetFK
        import rospy
        fk = rospy.ServiceProxy("/jaka_driver/get_fk", GetFK)(joint=POSE)
    finally:
        node.stop()
    assert f"URDF {install}/share/jaka_driver/urdf/jaka_zu5.urdf" in log
    assert f"IK library {install}/lib/libjaka_ik.so" in log
    assert list(fk.cartesian_pose) == pytest.approx(TCP_MM_ROTVEC, abs=0.1)


def test_catkin_doc_shows_the_commands():
    text = CATKIN_DOC.read_text()
    missing = [line for line in DOC_LINES if line not in text]
    assert not missing, f"docs/catkin.md lacks {missing}"
