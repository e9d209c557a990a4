"""How a request of the door answers: a refusal becomes its Result, any other exception a -3
answer, and simulated time stands still while the request is in the driver. Shared by
:class:`~.robot_driver.RobotDriver` and the door's parts (:mod:`.force_requests`), whose
methods it wraps; each of them has a ``clock`` (the backend's).
"""
from __future__ import annotations

import logging
from typing import Callable

from ..common.results import Code, CommandRefused, Result

log = logging.getLogger("jaka_driver.driver.robot_driver")     # the door's log, as before


def answers(method: Callable | None = None, *, react: bool = True) -> Callable:
    """Turn a refusal into its Result and any other exception into a -3 answer: a request may
    be refused, but it never takes the driver down. Simulated time stands still while a
    request is in the driver (jaka_driver.backend.clock): it acts at the sim time it arrived.
    ``react=False`` for requests a client streams once per cycle (servo_j, servo_p): their
    reply does not keep time waiting for the next call (the twin's clock waits for the next
    target instead). Use as ``@answers`` or ``@answers(react=False)``."""
    if method is None:
        return lambda m: answers(m, react=react)

    def wrapper(self, *args, **kwargs) -> Result:
        try:
            with self.clock.hold(react=react):
                return method(self, *args, **kwargs)
        except CommandRefused as refusal:
            return refusal.result()
        except Exception as exc:  # noqa: BLE001 — the node must survive any request
            log.exception("%s failed", method.__name__)
            return Result.failure(Code.COMMUNICATION_ERROR,
                                  f"{method.__name__} failed inside the driver: {exc!r}")

    wrapper.__name__ = method.__name__
    wrapper.__doc__ = method.__doc__
    return wrapper
