"""``robot_description`` with the mounting (docs/interface.md, "set_installation_angle"): the
launch's ``scripts/robot_description`` puts a ``world`` link above ``base_link`` whose fixed joint
turns the base by the installation angle (RPY ``(tilt_x, 0, rot_z)``, as a controller reads it
back), leaves the arm's own chain as the model file has it, and refuses an angle out of range
before anything starts."""
import math
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

from jaka_driver.common.installation import installation, mounted_description
from jaka_driver.common.models import repo_root
from jaka_driver.common.transforms import rpy_to_matrix

URDF = repo_root() / "urdf" / "jaka_zu5.urdf"
SCRIPT = repo_root() / "scripts" / "robot_description"


def tree(text):
    robot = ET.fromstring(text)
    links = {link.get("name") for link in robot.findall("link")}
    joints = {j.get("name"): j for j in robot.findall("joint")}
    children = {j.find("child").get("link") for j in joints.values()}
    return links, joints, children


def test_world_is_the_root_and_its_joint_turns_the_base_as_mounted():
    text = mounted_description(URDF.read_text(), installation(math.pi / 2, math.radians(30)))
    links, joints, children = tree(text)
    assert links - children == {"world"}                     # one root: the world
    joint = joints["world_joint"]
    assert joint.get("type") == "fixed" and joint.find("parent").get("link") == "world"
    assert joint.find("child").get("link") == "base_link"
    rpy = [float(v) for v in joint.find("origin").get("rpy").split()]
    # the base's orientation in the world is Rz(rot_z)·Rx(tilt_x): on a wall, its z is level
    turned = rpy_to_matrix(*rpy)
    assert turned[:, 2] == pytest.approx([math.sin(math.radians(30)),
                                          -math.cos(math.radians(30)), 0.0], abs=1e-12)
    plain_links, plain_joints, _ = tree(URDF.read_text())
    assert links == plain_links | {"world"} and set(joints) == set(plain_joints) | {"world_joint"}


def test_the_script_prints_it_and_refuses_an_angle_out_of_range():
    ok = subprocess.run([sys.executable, str(SCRIPT), "zu5", "--installation-angle", "[1.5708, 0]"],
                        capture_output=True, text=True, timeout=30)
    assert ok.returncode == 0, ok.stderr
    assert '<origin xyz="0 0 0" rpy="1.5708 0 0.0"/>' in ok.stdout
    bad = subprocess.run([sys.executable, str(SCRIPT), "zu5", "--installation-angle", "[3.5, 0]"],
                         capture_output=True, text=True, timeout=30)
    assert bad.returncode == 2 and "tilt_x is 3.5 rad" in bad.stderr and bad.stdout == ""
