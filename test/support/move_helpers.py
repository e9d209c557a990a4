"""Waiting for a move a backend started, for tests that drive a backend without RobotDriver
(which is what waits in the driver: jaka_driver.driver.moves.MoveRequests.run_move)."""
from __future__ import annotations

from jaka_driver.common.constants import move_deadline
from jaka_driver.common.results import Result


def run_move(started: Result) -> Result:
    """The move's final Result: ``started`` itself when the backend refused to start it, else
    what its completion finishes with (within the driver's own deadline for its plan)."""
    if not started.ok:
        return started
    completion, planned = started.value
    result = completion.wait(move_deadline(planned))
    assert result is not None, f"the move did not end within {move_deadline(planned):.1f} s " \
                               f"(planned {planned:.2f} s)"
    return result
