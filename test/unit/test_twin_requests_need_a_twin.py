"""The twin's own requests (faults, inputs, reset, pause, step) pass RobotDriver like every
other request: on a backend without a twin each is answered -9, nothing raised, and a bad
input is refused (-2) naming its field before the backend is asked."""
from fake_backend import FakeBackend

from jaka_driver.driver import RobotDriver


def test_every_twin_request_is_refused_without_a_twin():
    driver = RobotDriver(FakeBackend())
    assert not driver.twin.present
    for result in (driver.twin.emergency_stop(True), driver.twin.emergency_stop(False),
                   driver.twin.protective_stop(), driver.twin.set_input("digital", 0, 0, 1),
                   driver.twin.reset(), driver.twin.pause(True), driver.twin.step(1)):
        assert result.code == -9 and "not a twin" in result.message, result
    try:
        driver.twin.camera(80, 60)
    except RuntimeError as exc:
        assert "not a twin" in str(exc)
    else:
        raise AssertionError("a camera without a twin")


def test_a_bad_input_is_refused_naming_the_field():
    driver = RobotDriver(FakeBackend())
    for result, field in ((driver.twin.set_input("digitall", 0, 0, 1), "signal"),
                          (driver.twin.set_input("digital", 0, 500, 1), "index"),
                          (driver.twin.set_input("analog", 0, 0, float("nan")), "value")):
        assert result.code == -2 and field in result.message, result
