"""Every launch file's arguments are optional as roslaunch shows them: ``roslaunch --ros-args``
lists an ``<arg>`` without a default, or with an empty one, under "Required Arguments", and a
user reading that believes they must give it. The node reads the words the launch file
defaults to as "nothing": ``~scene`` none, ``~force_sensor`` model."""
import xml.etree.ElementTree as ET

import pytest

from jaka_driver.common.models import repo_root
from jaka_driver.ros.node import force_sensor_param, scene_param

LAUNCH_FILES = sorted((repo_root() / "launch").glob("*.launch"))


def test_there_are_launch_files():
    assert LAUNCH_FILES


@pytest.mark.parametrize("path", LAUNCH_FILES, ids=lambda p: p.name)
def test_every_argument_has_a_non_empty_default(path):
    # roslaunch's arg dump (roslaunch/arg_dump.py) counts an arg as required when its
    # default is missing or empty; an arg with a value is not shown at all
    required = [arg.get("name") for arg in ET.parse(path).getroot().iter("arg")
                if arg.get("value") is None and not arg.get("default")]
    assert required == [], f"{path.name}: {required} would be listed as required"


def test_the_launch_defaults_mean_no_scene_and_the_models_sensor():
    assert scene_param("none") is None and scene_param("") is None and scene_param(None) is None
    assert scene_param(" /w/table.yaml ") == "/w/table.yaml"
    assert force_sensor_param("model") is None and force_sensor_param("") is None
    assert force_sensor_param("true") is True
