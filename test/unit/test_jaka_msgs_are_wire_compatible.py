"""The generated jaka_msgs carry JAKA's md5 sums (docs/interface.md, "Messages
and wire compatibility"), so clients built against
JAKA's own package talk to this driver unchanged, and the ROS tools find the definitions."""
import os
import subprocess

import pytest

from jaka_msgs import msg, srv

CONTRACT_MD5 = {
    msg.RobotMsg: "cb4726a69178af69dc31d5013f095556",
    srv.Move: "bfcaec3e81ace5826d9d96166632c9d1",
    srv.ServoMove: "ea058e08a9ca2790743a486fd4bfb151",
    srv.ServoMoveEnable: "0fff944f16f37b02ba85acd57d94215a",
    srv.SetTcpFrame: "3d15cf469e59f026a4e4b350932a8496",
    srv.SetUserFrame: "f74c56afc671b9ccd78097ad9fa9b7ce",
    srv.SetPayload: "dbe0292cc6f9be694a93bf981dcc8471",
    srv.SetCollision: "192c4b02f65b62b6f0470ca351b4f7cc",
    srv.SetIO: "d70f55fb8350e7d75cb38e91f1bc0373",
    srv.GetIO: "6ff1cb5f4f299720705884f0c89f9d08",
    srv.GetFK: "10d9bfd5c1accf4678c49f520f9480b8",
    srv.GetIK: "33a7ddff09d4b5dc0322950ee926aea6",
    srv.ClearError: "0fff944f16f37b02ba85acd57d94215a",
    srv.ClearErr: "76c68a2c5e109f4d6a4dc1cfc355f405",
}


@pytest.mark.parametrize("type_", CONTRACT_MD5, ids=lambda t: t._type)
def test_md5_matches_jakas(type_):
    assert type_._md5sum == CONTRACT_MD5[type_]


def test_rossrv_and_rosmsg_show_the_definitions():
    out = subprocess.run(["rossrv", "show", "jaka_msgs/Move"], capture_output=True, text=True,
                         env=os.environ, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "float32[] pose" in out.stdout and "int16 ret" in out.stdout
    out = subprocess.run(["rosmsg", "show", "jaka_msgs/RobotMsg"], capture_output=True,
                         text=True, env=os.environ, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "int16 collision_state" in out.stdout


def test_messages_import_with_the_system_python_too():
    """rosservice/rostopic run on /usr/bin/python3, not the venv."""
    out = subprocess.run(["/usr/bin/python3", "-c", "from jaka_msgs.srv import Move; "
                          "print(Move._md5sum)"], capture_output=True, text=True, timeout=60)
    assert out.stdout.strip() == CONTRACT_MD5[srv.Move], out.stderr
