"""The one frame table of twin, emulator and controller: poses by id, id 0 the identity, an id
never stored reads as the identity and is reported once, what is read is a copy."""
import numpy as np

from jaka_driver.common.frames import TOOL, USER_FRAME, FrameTable
from jaka_driver.common.transforms import pose_mm_to_matrix

TOOL_1 = pose_mm_to_matrix([0, 0, 100, 0, 0, np.pi / 2])
USER_3 = pose_mm_to_matrix([300, -200, 50, 0, 0, 0.3])


def test_stored_frames_come_back_by_kind_and_id():
    table = FrameTable()
    table.store(TOOL, 1, TOOL_1)
    table.store(USER_FRAME, 3, USER_3)
    tool, user = table.active(1, 3)
    np.testing.assert_array_equal(tool, TOOL_1)
    np.testing.assert_array_equal(user, USER_3)
    np.testing.assert_array_equal(table.get(USER_FRAME, 1), np.eye(4))   # kinds are apart


def test_id_0_is_the_flange_and_the_base_whatever_is_stored():
    table = FrameTable()
    table.store(TOOL, 0, TOOL_1)
    table.store(USER_FRAME, 0, USER_3)
    for frame in table.active(0, 0):
        np.testing.assert_array_equal(frame, np.eye(4))


def test_an_unknown_id_is_the_identity_and_reported_once():
    reported = []
    table = FrameTable(on_unknown=lambda kind, i: reported.append((kind, i)))
    for _ in range(3):
        np.testing.assert_array_equal(table.get(TOOL, 7), np.eye(4))
    table.get(USER_FRAME, 7)
    assert reported == [(TOOL, 7), (USER_FRAME, 7)]


def test_what_is_read_cannot_change_the_table():
    table = FrameTable()
    table.store(TOOL, 2, TOOL_1)
    table.get(TOOL, 2)[0, 3] = 99.0
    np.testing.assert_array_equal(table.get(TOOL, 2), TOOL_1)


def test_the_shared_frames_are_the_kept_ones_until_stored_again_and_cannot_be_written():
    table = FrameTable()
    table.store(TOOL, 2, TOOL_1)
    tool, user = table.shared(2, 5)         # user 5 never stored: the identity
    assert tool is table.shared(2, 0)[0]    # the same array: a reader can cache by identity
    np.testing.assert_array_equal(tool, TOOL_1)
    np.testing.assert_array_equal(user, np.eye(4))
    for frame in (tool, user):
        assert not frame.flags.writeable
    table.store(TOOL, 2, USER_3)
    again, _ = table.shared(2, 0)
    assert again is not tool                # stored again: a new array, the old one unchanged
    np.testing.assert_array_equal(again, USER_3)
    np.testing.assert_array_equal(tool, TOOL_1)


def test_a_frame_stored_from_a_callers_array_is_not_changed_by_it():
    pose = TOOL_1.copy()
    table = FrameTable()
    table.store(TOOL, 1, pose)
    pose[0, 3] = 99.0
    np.testing.assert_array_equal(table.shared(1, 0)[0], TOOL_1)
