"""The suite's root. pytest.ini puts this directory on ``sys.path`` (``pythonpath = test``), so
every layer imports the shared helpers as one package, :mod:`support` (test/support/: the ROS
harness, the emulated arm, the fakes written from the evidence).

Layers: ``unit/`` needs nothing running and takes seconds; ``integration/`` runs real MuJoCo,
real TCP sockets and subprocesses but no rosmaster; ``ros/`` runs a real rosmaster and the real
node (every test there is marked ``ros``)."""
