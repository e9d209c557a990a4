"""What runs now on a controller has one owner, :class:`RunningMotion`: one slot (a move, a
trajectory, a jog or a velocity jog) with busy / abort / what a packet tells it, and servo
mode. Its rules (that no other part keeps a run: test_each_backend_writes_its_state_once)."""
import pytest

from jaka_driver.common.results import CommandRefused, Result
from jaka_driver.controller.move_watch import MoveWatch
from jaka_driver.controller.running_motion import JogRun, MoveRun, RunningMotion, keeps_out
from jaka_driver.controller.status_view import StatusView


def _move(label: str = "joint_move") -> MoveRun:
    return MoveRun(MoveWatch(label, lambda status: False))


def test_a_busy_move_keeps_a_new_move_out_naming_it_and_nothing_is_replaced():
    slot = RunningMotion(StatusView())
    first = _move()
    slot.take(first, keeps_out("joint_move"))
    with pytest.raises(CommandRefused) as refused:
        slot.take(_move("linear_move"), keeps_out("linear_move"))
    assert refused.value.code == -10
    assert refused.value.message == ("linear_move refused: joint_move is still running "
                                     "(stop_move first)")
    assert slot.current is first and slot.moving


def test_a_jog_keeps_nothing_out_and_a_busy_move_keeps_a_jog_out():
    slot = RunningMotion(StatusView())
    slot.take(JogRun(1, 0), keeps_out("jog"))
    move = _move()
    slot.take(move, keeps_out("joint_move"))          # a jog never blocks
    assert slot.current is move and slot.running(JogRun) is None
    with pytest.raises(CommandRefused):
        slot.check(keeps_out("jog"))


def test_abort_tells_the_waiter_which_motion_stopped_and_frees_the_slot():
    slot = RunningMotion(StatusView())
    move = _move("linear_move")
    slot.take(move, keeps_out("linear_move"))
    slot.abort(Result.failure(-12, "stopped by stop_move"))
    assert move.watch.completion.result.code == -12
    assert move.watch.completion.result.message == "linear_move: stopped by stop_move"
    assert not slot.moving
    slot.take(_move(), keeps_out("joint_move"))     # the slot takes the next one


def test_a_jog_ends_once():
    slot = RunningMotion(StatusView())
    slot.take(JogRun(1, 3), keeps_out("jog"))
    ended = slot.end_jog()
    assert ended is not None and ended.axis == (1, 3)
    assert slot.end_jog() is None and not slot.moving

