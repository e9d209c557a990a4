"""The suite's root. pytest.ini puts this directory on ``sys.path`` (``pythonpath = test``), so
every layer imports the shared helpers as one package, :mod:`support` (test/support/: the ROS
harness, the emulated arm, the fakes written from the evidence).

Layers: ``unit/`` needs nothing running and takes seconds; ``integration/`` runs real MuJoCo,
real TCP sockets and subprocesses but no rosmaster; ``ros/`` runs a real rosmaster and the real
node (every test there is marked ``ros``)."""

import warnings

# Debian's python3-actionlib has "\p" in two docstrings (goal_id_generator.py): Python warns
# when it first compiles the file, and in a fresh checkout that happens in whichever test
# imports it first (at collection the warning names no file, so pytest.ini cannot filter it
# by module). Not our code: compiled here once, quietly.
with warnings.catch_warnings():
    warnings.filterwarnings("ignore", "invalid escape sequence", DeprecationWarning)
    try:
        import actionlib.goal_id_generator  # noqa: F401
    except ImportError:                     # no ROS here: the layers that need it say so
        pass

#: Modules whose tests each start what they need (a roslaunch, a rostest, a twin per test): no
#: node, emulator or workspace shared by the module, so their tests may run on any worker
SPREAD = {"test/ros/test_every_model_starts_and_answers_get_fk.py",
          "test/ros/test_rostest_suites.py",
          "test/integration/test_every_model_twin_carries_its_rated_payload.py"}


def pytest_xdist_make_scheduler(config, log):
    """``make test`` runs the suite on pytest-xdist's worker processes: the tests of a module go
    to one worker, one after the other, so the node, emulator or catkin workspace the module
    shares is started once; the modules of :data:`SPREAD` go test by test. (xdist's own
    ``loadgroup`` marks cannot do it with pytest 9, whose node ids it can no longer rename.)
    Each worker has its own rosmaster (test/ros/conftest.py) and its own block of ports
    (support.ros_harness.free_port)."""
    from xdist.scheduler import LoadScopeScheduling

    class ModuleScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            module = nodeid.split("::", 1)[0]
            return nodeid if module in SPREAD else module

    return ModuleScheduling(config, log)
