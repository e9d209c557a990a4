"""The ``~joint_command`` topic reads JointTrajectory bytes itself (jaka_driver.ros.trajectory_wire):
against messages genpy serialised, it finds the positions genpy's own class finds, refuses what
the topic's rules refuse with the same words, and answers a short or garbled message only with
the DeserializationError rospy expects of a message class."""
from __future__ import annotations

import io
import itertools
import random

import genpy
import pytest
from std_msgs.msg import Header
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from jaka_driver.common.results import Result
from jaka_driver.ros.trajectory_wire import TrajectoryReader, TrajectoryTarget

JOINTS = [f"joint_{i}" for i in range(1, 7)]


def wire(msg: JointTrajectory) -> bytes:
    buff = io.BytesIO()
    msg.serialize(buff)
    return buff.getvalue()


def read(data: bytes, joints=JOINTS):
    return TrajectoryReader(joints).positions(TrajectoryTarget().deserialize(data))


def trajectory(names, *points, frame="base_link"):
    return JointTrajectory(header=Header(seq=7, frame_id=frame), joint_names=list(names),
                           points=list(points))


def point(positions, **more):
    return JointTrajectoryPoint(positions=list(positions), time_from_start=genpy.Duration(0.008),
                                **more)


def test_it_is_a_joint_trajectory_to_every_publisher():
    assert TrajectoryTarget._type == "trajectory_msgs/JointTrajectory"
    assert TrajectoryTarget._md5sum == JointTrajectory._md5sum
    assert TrajectoryTarget._full_text == JointTrajectory._full_text


def test_positions_in_the_model_order_whatever_order_the_names_came_in():
    targets = [0.1, -0.2, 0.3, -0.4, 0.5, -0.6]
    reader = TrajectoryReader(JOINTS)
    for order in itertools.islice(itertools.permutations(range(6)), 0, 720, 7):
        names = [JOINTS[i] for i in order]
        sent = [targets[i] for i in order]
        msg = trajectory(names, point(sent, velocities=[1.0] * 6, effort=[2.0] * 6),
                         frame="a frame with ünïcode")
        theirs = JointTrajectory().deserialize(wire(msg))
        by_name = dict(zip(theirs.joint_names, theirs.points[0].positions))
        assert reader.positions(TrajectoryTarget().deserialize(wire(msg))) == \
            [by_name[j] for j in JOINTS] == targets
    assert len(reader._orders) <= 16          # remembered orders stay bounded


@pytest.mark.parametrize("msg, words", [
    (trajectory(JOINTS), "points has 0 points, expected 1 (one servo target per message)"),
    (trajectory(JOINTS, point([0.0] * 6), point([0.1] * 6)), "points has 2 points, expected 1"),
    (trajectory(JOINTS[:5], point([0.0] * 5)),
     f"joint_names is {JOINTS[:5]}, expected the six joints {JOINTS} in any order"),
    (trajectory(JOINTS[:5] + ["joint_1"], point([0.0] * 6)),
     f"joint_names is {JOINTS[:5] + ['joint_1']}, expected the six joints"),
    (trajectory(JOINTS, point([0.0] * 5)), "points[0].positions has 5 values, expected 6"),
])
def test_refusals_name_the_field_the_value_and_the_limit(msg, words):
    result = read(wire(msg))
    assert isinstance(result, Result) and not result.ok
    assert words in result.message


def test_a_refused_name_list_is_refused_again_and_a_right_one_still_read():
    reader = TrajectoryReader(JOINTS)
    wrong = TrajectoryTarget().deserialize(wire(trajectory(JOINTS[:5] + ["x"], point([0] * 6))))
    right = TrajectoryTarget().deserialize(wire(trajectory(JOINTS, point(range(6)))))
    for _ in range(3):
        assert not reader.positions(wrong).ok
        assert reader.positions(right) == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]


def test_a_message_cut_short_of_what_it_reads_is_a_deserialization_error():
    msg = trajectory(JOINTS, point([0.5] * 6, velocities=[0.0] * 6), frame="base_link")
    data = wire(msg)
    # header, names, point count, the first point's positions: what the reader needs
    needed = (12 + 4 + len("base_link") + 4 + sum(4 + len(n) for n in JOINTS) + 4
              + 4 + 6 * 8)
    for cut in range(needed):
        with pytest.raises(genpy.DeserializationError):
            TrajectoryTarget().deserialize(data[:cut])
    for cut in range(needed, len(data) + 1):        # the rest it does not read
        assert read(data[:cut]) == [0.5] * 6


def test_random_bytes_never_raise_anything_but_a_deserialization_error():
    rng = random.Random(35)
    base = wire(trajectory(JOINTS, point([0.5] * 6)))
    for _ in range(3000):
        data = bytearray(base)
        for _ in range(rng.randint(1, 6)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        try:
            result = read(bytes(data))
        except genpy.DeserializationError:
            continue
        assert isinstance(result, (list, Result))
