"""The twin with a flange force/torque sensor, for the force tests: one started RobotDriver on a
zu5 SimBackend in simulated time (as fast as the machine steps), and each test's fresh start
on it. One set-up, so each test module says only what it checks."""
from __future__ import annotations

from contextlib import contextmanager
from typing import Optional

import pytest

from jaka_driver.common.models import load_model
from jaka_driver.driver import RobotDriver
from jaka_driver.programs import FolderPrograms
from jaka_driver.sim import SimBackend

MODEL = load_model("zu5")


@contextmanager
def twin_with_sensor(scene: Optional[str] = None, sensor: bool = True,
                     programs: Optional[str] = None):
    """A started driver on the zu5 twin (``sensor``: with its force/torque sensor, in the
    workcell ``scene``; ``programs`` its programs folder), shut down on leaving."""
    driver = RobotDriver(SimBackend(MODEL, scene=scene, sim_time=True, real_time_factor=0,
                                    force_sensor=sensor,
                                    programs=FolderPrograms(programs) if programs else None))
    driver.start()
    try:
        yield driver
    finally:
        driver.shutdown()


@pytest.fixture(scope="module")
def sensor_driver():
    """The started driver on the zu5 twin with its sensor that a test module's tests share."""
    with twin_with_sensor() as d:
        yield d


def fresh(driver, sensor_on: bool = False, settle: float = 0.05, zero: bool = False):
    """For a test fixture (``yield from fresh(driver)``): the twin reset, time held while the
    test runs (every step at a definite sim time); ``sensor_on``: the sensor switched on and
    read ``settle`` s, ``zero``: then zeroed."""
    assert driver.twin.reset().ok
    with driver.clock.hold():
        if sensor_on:
            assert driver.force.sensor_enable(True).ok
            driver.clock.sleep(settle)
        if zero:
            assert driver.force.zero_sensor().ok
        yield driver
