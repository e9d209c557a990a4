"""Every service can be called from a shell with `rosservice call`, using the interface
document's field names and units, and the README's examples are exactly these command lines.

The examples run in order against one real node on the zu5 twin (each prepares the next: servo
mode is entered before `servo_j`, the arm is released from drag mode before it must move...).
`rosservice`/`rostopic` are the real Debian command-line tools, started as a user would.
"""
from __future__ import annotations

import os
import shlex
import subprocess
from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.ros

README = Path(__file__).resolve().parents[2] / "README.md"
SNAPSHOT_PATH = "/tmp/jaka_arm.png"     # as in README; the test writes to its own folder

# The pose of the README picture; get_fk and linear_move below use its TCP (mm, rotation vector),
# servo_p the same TCP in m + RPY with joint_6 at 0.01 rad, 1 mm higher.
POSE = "[0.5, 1.9, -1.4, 1.1, 1.57, 0]"
TCP_MM_ROTVEC = [209.5, 244.3, 600.1, -2.681, 1.590, -0.024]

# (command line exactly as README shows it, fields the answer must have)
EXAMPLES = [
    (f'rosservice call /jaka_driver/joint_move "{{pose: {POSE}, mvvelo: 1.0, mvacc: 2.0}}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/servo_move_enable "{enable: true}"', {"ret": 1}),
    ('rosservice call /jaka_driver/servo_j "{pose: [0.5, 1.9, -1.4, 1.1, 1.57, 0.01]}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/servo_p '
     '"{pose: [0.2095, 0.2443, 0.6011, -3.1124, -0.0005, -1.0808]}"', {"ret": 1}),
    ('rosservice call /jaka_driver/servo_move_enable "{enable: false}"', {"ret": 1}),
    (f'rosservice call /jaka_driver/get_fk "{{joint: {POSE}}}"',
     {"cartesian_pose": TCP_MM_ROTVEC}),
    ('rosservice call /jaka_driver/linear_move '
     '"{pose: [209.5, 244.3, 550.1, -2.681, 1.590, -0.024], mvvelo: 100, mvacc: 500}"',
     {"ret": 1}),
    (f'rosservice call /jaka_driver/get_ik "{{ref_joint: {POSE}, '
     'cartesian_pose: [209.5, 244.3, 550.1, -2.681, 1.590, -0.024]}"', {"joint": "6 angles"}),
    ('rosservice call /jaka_driver/jog "{coord_mode: 0, index: 10, mvvelo: 0.2}"', {"ret": 1}),
    ('rosservice call /jaka_driver/stop_move "{}"', {}),
    ('rosservice call /jaka_driver/set_toolframe "{tool_num: 1, pose: [0, 0, 100, 0, 0, 0]}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/set_userframe "{user_num: 1, pose: [400, 0, 0, 0, 0, 0]}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/set_payload "{tool_num: 1, mass: 2.5, xc: 0, yc: 0, zc: 60}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/set_collisionlevel "{is_enable: true, value: 50}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/set_io "{signal: digital, type: 0, index: 3, value: 1}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/get_io "{signal: digital, path: 1, type: 0, index: 3}"',
     {"value": 1.0}),
    ('rosservice call /jaka_driver/drag_mode "{data: true}"', {"success": True}),
    ('rosservice call /jaka_driver/drag_move "{data: false}"', {"success": True}),
    ('rosservice call /jaka_driver/sim/protective_stop "{}"', {"success": True}),
    ('rosservice call /jaka_driver/clear_err "{}"', {"ret": 1}),
    ('rosservice call /jaka_driver/sim/emergency_stop "{data: true}"', {"success": True}),
    ('rosservice call /jaka_driver/sim/emergency_stop "{data: false}"', {"success": True}),
    ('rosservice call /jaka_driver/power "{data: true}"', {"success": True}),
    ('rosservice call /jaka_driver/enable "{data: true}"', {"success": True}),
    ('rosservice call /jaka_driver/clear_error "{}"', {"ret": 1}),
    ('rosservice call /jaka_driver/sim/set_input "{signal: digital, type: 0, index: 2, value: 1}"',
     {"ret": 1}),
    ('rosservice call /jaka_driver/get_io "{signal: digital, path: 0, type: 0, index: 2}"',
     {"value": 1.0}),
    (f"rosparam set /jaka_driver/snapshot_path {SNAPSHOT_PATH}", None),
    ('rosservice call /jaka_driver/sim/snapshot "{}"', {"success": True}),
]

TOPICS = ["/jaka_driver/tool_position", "/jaka_driver/joint_position",
          "/jaka_driver/robot_states", "/joint_states"]
CONTRACT_SERVICES = [
    "joint_move", "linear_move", "jog", "servo_move_enable", "servo_j", "servo_p", "stop_move",
    "set_toolframe", "set_userframe", "set_payload", "drag_mode", "drag_move",
    "set_collisionlevel", "set_io", "get_io", "clear_err", "clear_error", "get_fk", "get_ik"]


def run(command: str, tmp: Path, timeout: float = 30.0) -> subprocess.CompletedProcess:
    argv = [a.replace(SNAPSHOT_PATH, str(tmp / "arm.png")) for a in shlex.split(command)]
    return subprocess.run(argv, capture_output=True, text=True, timeout=timeout,
                          env=os.environ.copy())


@pytest.fixture(scope="module")
def cli_tmp(tmp_path_factory):
    return tmp_path_factory.mktemp("cli")


@pytest.mark.parametrize("command,expect", EXAMPLES,
                         ids=[c.split()[2].rsplit("/", 1)[-1] if c.startswith("rosservice")
                              else "rosparam" for c, _ in EXAMPLES])
def test_example_runs_and_answers_success(sim_driver, cli_tmp, command, expect):
    out = run(command, cli_tmp)
    assert out.returncode == 0, f"{command}\n{out.stdout}{out.stderr}\n{sim_driver.log()}"
    if expect is None:
        return
    answer = yaml.safe_load(out.stdout) or {}
    for field, want in expect.items():
        assert field in answer, f"{command}: no field {field!r} in\n{out.stdout}"
        got = answer[field]
        if want == "6 angles":
            assert len(got) == 6 and max(abs(v) for v in got) < 7, out.stdout
        elif isinstance(want, list):
            assert got == pytest.approx(want, abs=0.1), out.stdout
        else:
            assert got == want, f"{command}\n{out.stdout}"
    if "sim/snapshot" in command:
        picture = cli_tmp / "arm.png"
        assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert str(picture) in answer["message"]


def test_state_topics_echo_from_the_shell(sim_driver, cli_tmp):
    for topic in TOPICS:
        out = run(f"rostopic echo -n1 {topic}", cli_tmp)
        assert out.returncode == 0 and "---" in out.stdout, f"{topic}: {out.stderr}"


def test_list_commands_show_the_contract_names(sim_driver, cli_tmp):
    services = set(run("rosservice list", cli_tmp).stdout.split())
    missing = [s for s in CONTRACT_SERVICES if f"/jaka_driver/{s}" not in services]
    assert not missing, f"rosservice list lacks {missing}"
    topics = set(run("rostopic list", cli_tmp).stdout.split())
    assert set(TOPICS) <= topics, f"rostopic list lacks {set(TOPICS) - topics}"


def test_readme_shows_every_example():
    """The README's CLI section is this file's EXAMPLES, character for character."""
    text = README.read_text()
    missing = [c for c, _ in EXAMPLES if c not in text]
    assert not missing, "README.md lacks these examples:\n" + "\n".join(missing)
