"""The rostest suites a user runs with `rostest jaka_driver <name>.test` pass (each starts its
own master, the launch file and its test nodes)."""
import os
import subprocess

import pytest

pytestmark = pytest.mark.ros


@pytest.mark.parametrize("suite", ["bringup.test", "motion_scenario.test", "multi_robot.test",
                                   "sim_time_program.test", "twin_reset_between_tests.test",
                                   "program_pause_resume.test", "press_on_table.test",
                                   "vision_guided_pick.test", "pick_and_place.test"])
def test_rostest_suite_passes(suite, tmp_path):
    env = dict(os.environ, ROS_HOME=str(tmp_path), ROS_LOG_DIR=str(tmp_path / "log"))
    env.pop("ROS_MASTER_URI", None)
    out = subprocess.run(["rostest", "jaka_driver", suite], capture_output=True, text=True,
                         env=env, timeout=300)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-2000:]
