"""The emulator's motion queue never looks done while a queued move is being started.

A controller reports ``inpos`` false and ``wait_complete`` waits from the moment a move is
queued until the last queued move has ended. The emulator's queue worker takes the next move
off the queue and then starts it (planning takes time); in that gap the queue is empty and
the twin not yet driven, and ``inpos`` / ``wait_complete`` must still say "moving". The test
holds a queued move in its start for as long as it likes (real zu5 twin, its physics thread
not running: the move is only started, never stepped).
"""
import threading

import numpy as np

from jaka_driver.common.models import load_model
from jaka_driver.emulator.twin_controller import TwinController
from jaka_driver.sim import SimBackend


def test_the_queue_is_not_done_while_its_next_move_is_being_started():
    twin = SimBackend(load_model("zu5"))
    controller = TwinController(twin)
    starting, release = threading.Event(), threading.Event()

    def slow_start():
        starting.set()
        release.wait(5.0)                # planning, as long as the test wants
        goal = twin.twin.commanded_joints() + np.radians([10.0, 0, 0, 0, 0, 0])
        return twin.start_joint_move(goal, 1.0, 4.0)

    try:
        controller.queue.enqueue("joint_move", slow_start)
        assert starting.wait(5.0)
        assert controller.queued == 0                    # taken off the queue...
        seen = [controller.inpos for _ in range(50)]     # ...and not started yet
        assert not any(seen), "inpos true between the queue and the move's start"
        assert not controller.wait_idle(0.2), "wait_complete would answer during the start"
        release.set()
        threading.Event().wait(0.2)
        assert controller.moving and not controller.inpos  # started: the twin drives it now
    finally:
        release.set()
        controller.close()
        twin.shutdown()
