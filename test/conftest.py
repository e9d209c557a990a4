"""The suite's root. pytest.ini puts this directory on ``sys.path`` (``pythonpath = test``), so
every layer imports the shared helpers as one package, :mod:`support` (test/support/: the ROS
harness, the emulated arm, the fakes written from the evidence).

Layers: ``unit/`` needs nothing running and takes seconds; ``integration/`` runs real MuJoCo,
real TCP sockets and subprocesses but no rosmaster; ``ros/`` runs a real rosmaster and the real
node (every test there is marked ``ros``)."""
import pytest


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """``make test`` runs the suite on pytest-xdist's workers with ``--dist loadgroup``: the tests
    of a module go to one worker, one after the other, so the node, emulator or catkin workspace
    the module shares is started once; a module marked ``independent`` (a roslaunch or a twin
    per test) is spread over the workers test by test. Each worker has its own rosmaster
    (test/ros/conftest.py) and its own block of ports (support.ros_harness.free_port). (xdist
    shows the group after a test's name: ``…::test_x@test_module``.)"""
    for item in items:
        if item.get_closest_marker("independent") is None:
            item.add_marker(pytest.mark.xdist_group(item.path.stem))
