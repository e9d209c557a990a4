"""The node reaches the arm only through RobotDriver: no module of ``ros/`` touches
``driver.backend`` or a twin's capability (``backend.twin.…``: only the door's ``driver.twin.…``,
:class:`~jaka_driver.driver.twin_requests.TwinRequests`), so every request — the twin's faults,
inputs, reset, pause and step too — is checked and timed by the door (in sim time, between two
cycles). Static reads of the files; nothing is imported or started."""
import re
from pathlib import Path

ROS = Path(__file__).resolve().parents[2] / "src" / "jaka_driver" / "ros"
AROUND_THE_DOOR = re.compile(r"driver\.backend|(?<!driver)\.twin\.")


def test_no_module_of_the_node_reaches_around_robot_driver():
    modules = sorted(ROS.glob("*.py"))
    assert len(modules) > 10
    found = [f"{path.name}:{n}: {line.strip()}" for path in modules
             for n, line in enumerate(path.read_text().splitlines(), 1)
             if AROUND_THE_DOOR.search(line)]
    assert not found, "\n".join(found)
