"""Every sample a twin produces, for tests that measure a whole motion: a consumer of the twin's
samples (with simulated time the twin waits for it, so none is missed); and a started driver on
a twin in simulated time that keeps them (:func:`collected_twin`)."""
from __future__ import annotations

import threading
import time

from jaka_driver.backend.robot_state import RobotState
from jaka_driver.common.constants import SERVO_CYCLE
from jaka_driver.common.models import RobotModel
from jaka_driver.driver import RobotDriver
from jaka_driver.sim import SimBackend


class Collector:
    """Every sample of ``driver``'s backend from now on, in ``states`` (oldest first) and by
    cycle number in ``q`` / ``qd`` (joints rad, rad/s)."""

    def __init__(self, driver):
        self.driver = driver
        self.states: list[RobotState] = []
        self.q, self.qd = {}, {}
        self._done = threading.Event()
        driver.clock.add_consumer()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        last = -1.0
        while not self._done.is_set():
            self.driver.wait_for_sample(last, 0.05)
            for st in self.driver.states_since(last):
                n = round(st.stamp / SERVO_CYCLE)
                self.q[n], self.qd[n] = st.joint_position.copy(), st.joint_velocity.copy()
                self.states.append(st)
                last = st.stamp
            self.driver.clock.consumed(last)

    def since(self, stamp: float, until: float | None = None) -> list[RobotState]:
        """The samples stamped after ``stamp`` (s) — with ``until`` (s), once the collector
        has reached a sample stamped then (it may be a few cycles behind the twin)."""
        if until is not None:
            deadline = time.monotonic() + 10.0
            while not (self.states and self.states[-1].stamp >= until):
                assert time.monotonic() < deadline, f"no sample stamped {until:.3f} s yet"
                time.sleep(0.005)
        return [st for st in list(self.states) if st.stamp > stamp]

    def close(self):
        self._done.set()
        self._thread.join(2.0)


def collected_twin(model: RobotModel, **backend):
    """A started :class:`RobotDriver` on a twin of ``model`` in simulated time, stepping as fast
    as it can (``backend``: more of SimBackend's arguments), its samples in
    ``driver.samples`` (a :class:`Collector`); shut down when the generator ends (a fixture's
    ``yield from``)."""
    driver = RobotDriver(SimBackend(model, sim_time=True, real_time_factor=0, **backend))
    driver.samples = Collector(driver)
    driver.start()
    try:
        yield driver
    finally:
        driver.samples.close()
        driver.shutdown()
