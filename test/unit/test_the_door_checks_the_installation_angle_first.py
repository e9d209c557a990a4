"""The installation angle at the door (docs/interface.md, "set_installation_angle"): JAKA's
ranges are checked before anything (-2 naming field, value and limit), then the arm's state —
refused while a move runs (-10), since the move was planned under the old gravity — and only then
is the backend asked, with the checked mounting. A refused request reaches no backend."""
import math
import threading
import time

from fake_backend import FakeBackend

from jaka_driver.common.results import Code, Result
from jaka_driver.driver import RobotDriver

TARGET = [0.5, 1.5, -1.5, 1.5, 1.5, 0.0]


class MountableBackend(FakeBackend):
    def set_installation_angle(self, mounting):
        return self._called("set_installation_angle", mounting)


def test_out_of_range_angles_are_refused_before_the_backend_hears_of_them():
    backend = MountableBackend()
    driver = RobotDriver(backend)
    for tilt, rot, named in ((math.pi + 0.01, 0.0, "tilt_x"), (0.0, -0.5, "rot_z"),
                             (float("inf"), 0.0, "tilt_x"), ("wall", 0.0, "tilt_x")):
        refused = driver.set_installation_angle(tilt, rot)
        assert refused.code == Code.INVALID_PARAMETER and refused.message.startswith(named)
        assert "[0, " in refused.message and "°)" in refused.message
    assert "set_installation_angle" not in backend.names()


def test_while_a_move_runs_the_angle_is_refused_and_afterwards_it_is_passed_on():
    backend = MountableBackend(planned=5.0)
    driver = RobotDriver(backend)
    box = {}
    thread = threading.Thread(target=lambda: box.update(r=driver.joint_move(TARGET, 1.0, 2.0)))
    thread.start()
    deadline = time.monotonic() + 2.0
    while backend.move is None and time.monotonic() < deadline:
        time.sleep(0.005)
    refused = driver.set_installation_angle(math.pi / 2, 0.0)
    assert refused.code == Code.BUSY and "moves" in refused.message
    assert "set_installation_angle" not in backend.names()
    backend.finish_move(Result.success("in position"))
    thread.join(2.0)
    assert driver.set_installation_angle(math.pi / 2, 0.25).ok
    (mounting,) = [c[1] for c in backend.calls if c[0] == "set_installation_angle"]
    assert (mounting.tilt_x, mounting.rot_z) == (math.pi / 2, 0.25)
