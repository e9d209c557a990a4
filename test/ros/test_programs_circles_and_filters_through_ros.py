"""circular_move, the program services and topic, and set_servo_filter through ROS on the zu5
twin: an arc measured on tool_position stays within 0.1 mm of its circle and collinear points
are refused naming the tolerance; a program is loaded (".jks" taken off), its variables read and
set, played, paused (robot_states.motion_state 1, the latched program/state says paused at its
line), stopped; the servo filter is chosen, refused in servo mode, and shown in /diagnostics;
~io_states carries every IO kind of the arm, shows an output set_io changed within one sample
(counted in joint_position samples, not wall time) and runs at 10 Hz or more of sample time;
the README's examples run as written."""
import os
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest
import rosservice
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import TwistStamped
from jaka_msgs.msg import RobotMsg
from jaka_msgs.srv import GetFK, ServoMoveEnable, SetIO

from support.ros_harness import START, Recorder, go_home, wait_until
from jaka_driver.motion.circular_path import arc_through
from jaka_driver_msgs.msg import IOStates, ProgramState
from jaka_driver_msgs.srv import (CircularMove, GetLoadedProgram, GetProgramVariables,
                                  LoadProgram, ProgramCommand, SetProgramVariable,
                                  SetServoFilter)

pytestmark = pytest.mark.ros

NEW_SERVICES = {"circular_move", "set_servo_filter", "program/load", "program/loaded",
                "program/play", "program/pause", "program/resume", "program/stop",
                "program/get_variables", "program/set_variable"}


@pytest.fixture(scope="module")
def program_state(sim_driver, rospy_node):
    recorder = Recorder(sim_driver.name("program/state"), ProgramState)
    yield recorder
    recorder.close()


def test_the_node_serves_circles_programs_and_the_filter(sim_driver, program_state):
    served = {name.split("/jaka_driver/", 1)[1] for name in rosservice.get_service_list()
              if name.startswith("/jaka_driver/")}
    assert NEW_SERVICES <= served, NEW_SERVICES - served
    first = wait_until(program_state.latest, 5.0)          # latched: there at once
    assert (first.state, first.state_name, first.name, first.line) == (0, "idle", "", 0)


def test_an_arc_through_ros_stays_within_0_1_mm_of_its_circle(call, tcp):
    go_home(call)
    start = np.array(call("get_fk", GetFK, joint=START).cartesian_pose)
    center = start[:3] + [80.0, 0.0, 0.0]
    mid = np.concatenate([center + [0.0, 80.0, 0.0], start[3:]])
    end = np.concatenate([center + [80.0, 0.0, 0.0], start[3:]])
    t0 = time.time()
    reply = call("circular_move", CircularMove, pose_mid=list(mid), pose_end=list(end),
                 mvvelo=150.0, mvacc=800.0, turns=0.5, attitude_mode=0, coord_mode=0)
    assert reply.ret == 1, reply.message
    samples = np.array([[m.twist.linear.x, m.twist.linear.y, m.twist.linear.z]
                        for _, m in tcp.since(t0)])
    circle = arc_through(start[:3] / 1000, mid[:3] / 1000, end[:3] / 1000)
    assert len(samples) > 200                                # ~2.7 s at 125 Hz
    assert circle.distance_from(samples).max() * 1000 < 0.1
    # half a turn beyond the end point: diametrically opposite it
    np.testing.assert_allclose(samples[-1] * 1000, center - [80.0, 0.0, 0.0], atol=0.05)
    on_line = np.concatenate([(start[:3] + end[:3]) / 2, start[3:]])
    refused = call("circular_move", CircularMove, pose_mid=list(on_line), pose_end=list(end),
                   mvvelo=150.0, mvacc=800.0, turns=0, attitude_mode=0, coord_mode=0)
    assert refused.ret == -2 and "0.1 mm needed to define a circle" in refused.message


def test_a_program_is_loaded_read_set_played_paused_and_stopped(call, states, program_state):
    go_home(call)
    assert call("program/load", LoadProgram, name="pick_cycle.jks").ret == 1
    assert call("program/loaded", GetLoadedProgram).name == "pick_cycle"
    listed = call("program/get_variables", GetProgramVariables)
    assert (list(listed.id), list(listed.value), list(listed.alias)) == \
        ([1, 2, 3], [2.0, 0.0, 1.0], ["cycles", "done", "go"])
    assert call("program/set_variable", SetProgramVariable, id=3, value=0, alias="").ret == 1
    assert call("program/get_variables", GetProgramVariables).value[2] == 0.0
    assert call("program/set_variable", SetProgramVariable, id=4, value=0,
                alias="").ret == -2
    assert call("program/play", ProgramCommand).ret == 1
    # waiting for its go (line 9): running, motion_state 3
    assert wait_until(lambda: (m := program_state.latest()) and m.line == 9, 5.0)
    assert wait_until(lambda: states.latest().motion_state == 3, 2.0)
    assert call("program/pause", ProgramCommand).ret == 1
    paused = wait_until(lambda: (m := program_state.latest()) and m.state_name == "paused"
                        and m, 2.0)
    assert paused and (paused.state, paused.line) == (ProgramState.PAUSED, 9)
    assert wait_until(lambda: states.latest().motion_state == 1, 2.0)
    assert call("program/resume", ProgramCommand).ret == 1
    assert call("program/stop", ProgramCommand).ret == 1
    stopped = wait_until(lambda: (m := program_state.latest()) and m.state == 0 and m, 5.0)
    assert stopped and (stopped.line, stopped.error) == (0, "")
    assert wait_until(lambda: states.latest().motion_state == 0, 2.0)
    assert call("program/resume", ProgramCommand).ret == -9        # nothing paused


def test_the_servo_filter_is_chosen_outside_servo_mode_and_shown_in_diagnostics(
        call, sim_driver, rospy_node):
    go_home(call)
    reply = call("set_servo_filter", SetServoFilter, filter_type=3, mmf_buffer=20, mmf_kp=0.2,
                 mmf_kv=0.4, mmf_ka=0.2)
    assert reply.ret == 1, reply.message
    diagnostics = Recorder("/diagnostics", DiagnosticArray)
    try:
        def shown():
            msg = diagnostics.latest()
            values = {kv.key: kv.value for kv in msg.status[0].values} if msg else {}
            return values.get("servo_filter")
        assert wait_until(shown, 5.0) == ("joint multi-order mean (buffer 20, kp 0.2, kv 0.4, "
                                          "ka 0.2)")
    finally:
        diagnostics.close()
    assert call("servo_move_enable", ServoMoveEnable, enable=True).ret == 1
    try:
        refused = call("set_servo_filter", SetServoFilter, filter_type=0)
        assert refused.ret == -9 and "servo mode" in refused.message
    finally:
        assert call("servo_move_enable", ServoMoveEnable, enable=False).ret == 1
    out = call("set_servo_filter", SetServoFilter, filter_type=1, lpf_cutoff_hz=100.0)
    assert out.ret == -2 and "lpf_cutoff_hz is 100 Hz, expected [0.01, 62.5] Hz" in out.message
    assert call("set_servo_filter", SetServoFilter, filter_type=0).ret == 1


def test_io_states_shows_an_output_within_one_sample_of_set_io(call, sim_driver, joints):
    io = Recorder(sim_driver.name("io_states"), IOStates)
    try:
        first = wait_until(io.latest, 5.0)                       # latched: there at once
        groups = {g.type: g for g in first.groups}
        assert sorted(groups) == [0, 1, 2] and groups[0].name == "cabinet"
        assert (len(groups[0].digital_out), len(groups[1].digital_in)) == (16, 2)  # zu5's
        assert call("set_io", SetIO, signal="digital", type=0, index=5, value=1).ret == 1
        answered = time.time()
        shown = wait_until(lambda: next((m for _, m in io.since(answered - 1.0)
                                         if m.groups[0].digital_out[5]), None), 2.0)
        assert shown, "~io_states never showed cabinet output 5"
        # the first joint_position sample received after set_io answered may have been on
        # its way already: the output shows in it or in the next one
        after = wait_until(lambda: next((m for t, m in joints.since(answered)), None), 2.0)
        between = [m for _, m in joints.since(answered - 1.0)
                   if after.header.stamp <= m.header.stamp < shown.header.stamp]
        assert len(between) <= 1, [m.header.stamp.to_sec() for m in between]
        # unchanged, it is published again every 0.1 s of sample time: to the next 8 ms
        # sample (a stalled physics cycle, on a loaded machine, may stretch one gap)
        t0 = time.time()
        time.sleep(1.2)
        stamps = [m.header.stamp.to_sec() for _, m in io.since(t0)]
        assert len(stamps) >= 10, stamps
        assert np.percentile(np.diff(stamps), 90) <= 0.1 + 0.008 + 1e-6, stamps
    finally:
        assert call("set_io", SetIO, signal="digital", type=0, index=5, value=0).ret == 1
        io.close()


README = Path(__file__).resolve().parents[2] / "README.md"


def readme_line(start: str) -> str:
    lines = [line for line in README.read_text().splitlines() if line.startswith(start)]
    assert len(lines) == 1, f"README.md has {len(lines)} lines starting {start!r}"
    return lines[0]


@pytest.mark.parametrize("start, answers", [
    ("rosservice call /jaka_driver/circular_move", ["ret: 1"]),
    ("rosservice call /jaka_driver/set_servo_filter", ["ret: 1"]),
    ("rosservice call /jaka_driver/program/load", ["ret: 1", "ret: 1", "state_name: \"running\"",
                                                    "name: \"three_moves\""]),
    ("rostopic echo -n1 /jaka_driver/io_states", ["name: \"cabinet\"", "name: \"tool\"",
                                                   "name: \"extension\""]),
])
def test_the_readmes_examples_run_as_written(call, program_state, start, answers):
    go_home(call)
    out = subprocess.run(["bash", "-c", readme_line(start)], capture_output=True, text=True,
                         timeout=60, env=os.environ.copy())
    assert out.returncode == 0, out.stdout + out.stderr
    position = 0
    for answer in answers:                       # in this order in the output
        found = out.stdout.find(answer, position)
        assert found >= 0, f"{answer!r} not in\n{out.stdout}"
        position = found + len(answer)
    assert call("program/stop", ProgramCommand).ret == 1
    assert call("set_servo_filter", SetServoFilter, filter_type=0).ret == 1
