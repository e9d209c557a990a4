"""What only a twin can do, through the door: ``driver.twin`` (:class:`TwinRequests`), the one
door of the ``backend.twin`` facet — its faults and inputs (the world acting on the arm,
the hand on its tool included), its reset, the pause and steps of its simulated time, and its
camera. In simulated time each acts between two cycles, at the sim time it arrived, as every
request does. On a backend without a twin each is answered -9.
"""
from __future__ import annotations

from typing import Callable, Sequence

from ..backend import Camera, Twin
from ..backend import force_checks as fcheck
from ..common.results import Code, CommandRefused, Result, invalid
from . import checks as check
from .door import Door, RequestPart, answers

#: Why a twin's own request is refused on a controller (-9).
NOT_A_TWIN = ("refused: this backend is a controller, not a twin (reset, pause and step are "
              "the twin's own)")
NOT_A_TWIN_FAULTS = ("refused: this backend is a controller, not a twin (faults and inputs "
                     "are injected on a twin only)")
#: the most cycles one step request runs (80 s of sim time)
MAX_STEP = 10000


class TwinRequests(RequestPart):
    """The twin's own requests (see the module); ``forget_servo()`` makes the servo stream start
    afresh after a reset."""

    def __init__(self, door: Door, forget_servo: Callable[[], None]):
        super().__init__(door)
        self._forget_servo = forget_servo
        self._after_reset: list[Callable[[], Result]] = []

    def after_reset(self, set_up: Callable[[], Result]) -> None:
        """Run ``set_up()`` after each reset that succeeded (a device on the tool connector set
        up again as at start: the reset switched the tool supply off and deleted the signals)."""
        self._after_reset.append(set_up)

    @property
    def present(self) -> bool:
        """The backend offers what only a twin can do (:class:`~jaka_driver.backend.Twin`):
        the node then serves its fault, input, hand and snapshot services."""
        return self.backend.twin is not None

    def _twin(self, refusal: str) -> Twin:
        """The backend's twin; without one, a -9 refusal saying ``refusal``."""
        twin = self.backend.twin
        if twin is None:
            raise CommandRefused(Code.WRONG_MODE, refusal)
        return twin

    def parts(self) -> dict:
        """Where the twin's parts are: name → 4x4 pose (m, base frame); empty without a twin
        or parts. A read: it holds no time."""
        twin = self.backend.twin
        return {} if twin is None else twin.parts()

    @answers
    def emergency_stop(self, pressed: bool) -> Result:
        """Press (True) or release (False) the twin's emergency stop. In sim time it happens
        between two cycles, at the sim time the request arrived, as every request does."""
        twin = self._twin(f"emergency stop {NOT_A_TWIN_FAULTS}")
        return twin.press_emergency_stop() if pressed else twin.release_emergency_stop()

    @answers
    def protective_stop(self) -> Result:
        """A protective stop on the twin, as after a collision; clear_err recovers."""
        return self._twin(f"protective stop {NOT_A_TWIN_FAULTS}").trigger_protective_stop()

    @answers
    def set_input(self, signal: str, type: int, index: int, value: float) -> Result:  # noqa: A002
        """Drive the twin's input ``index`` (from 0) of ``signal`` on IO ``type`` to ``value``
        as the outside world would (digital non-zero → 1, analog V)."""
        sig = check.io_signal(signal)
        check.io_address(self.model, sig, 0, type, index)
        v = check.io_value(sig, value)
        return self._twin(f"set_input {NOT_A_TWIN_FAULTS}").set_input(sig, int(type),
                                                                       int(index), v)

    @answers
    def reset(self, joints: Sequence[float] = ()) -> Result:
        """A twin back to a fresh start (:meth:`jaka_driver.backend.Twin.reset`) at ``joints``
        (rad; empty: home); the driver forgets its jogs and servo stream. -9 without a twin.
        In sim time it happens between two cycles, at the sim time the request arrived."""
        twin = self._twin(f"reset {NOT_A_TWIN}")
        q = check.joint_targets("joints", joints, self.model) if len(joints) else None
        self.door.forget_jogs()
        self._forget_servo()
        result = twin.reset(q)
        for set_up in self._after_reset if result.ok else ():
            again = set_up()
            if not again.ok:            # the reset happened: say so, and what did not
                return Result(result.code, f"{result.message}; setting up again after it was "
                              f"refused ({again.code}): {again.message}", result.value)
        return result

    @answers
    def pause(self, pause: bool) -> Result:
        """Stop (True) or run on (False) the twin's simulated time."""
        twin = self._twin(NOT_A_TWIN)
        return twin.pause() if pause else twin.unpause()

    @answers
    def step(self, cycles: int) -> Result:
        """While paused, run ``cycles`` (1–:data:`MAX_STEP`) 8 ms cycles; ``Result.value`` is the
        sim time (s) after them."""
        twin = self._twin(NOT_A_TWIN)
        if not 1 <= cycles <= MAX_STEP:
            raise invalid(f"cycles is {cycles}, expected 1–{MAX_STEP}")
        return twin.step(cycles)

    @answers
    def push_tool(self, wrench: Sequence[float], duration: float) -> Result:
        """Push the twin's tool (Twin.push_tool), as an operator's hand: ``wrench`` N and N·m
        along the base's axes, for ``duration`` s (0: let go). -9 on a controller."""
        twin = self._twin("push_tool refused: this backend is a controller, not a twin (push "
                          "the real tool by hand)")
        w, t = fcheck.push(wrench, duration)
        return twin.push_tool(w, t)

    def camera(self, width: int, height: int) -> Camera:
        """The twin's offscreen camera (:meth:`jaka_driver.backend.Twin.camera`: made in the
        thread that renders with it; raises ImportError or RuntimeError where rendering is
        unavailable, RuntimeError without a twin)."""
        twin = self.backend.twin
        if twin is None:
            raise RuntimeError(f"no camera: {NOT_A_TWIN_FAULTS}")
        return twin.camera(width, height)
