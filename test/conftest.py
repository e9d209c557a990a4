"""The suite's root. Its directory goes on ``sys.path`` (pytest's prepend import mode), so every
layer imports the shared harness modules: ``ros_harness`` (rosmaster, node, recorders, the arm's
clean slate) and ``pictures`` (reading the twin's PNGs back).

Layers: ``unit/`` needs nothing running and takes seconds; ``integration/`` runs real MuJoCo,
real TCP sockets and subprocesses but no rosmaster; ``ros/`` runs a real rosmaster and the real
node (every test there is marked ``ros``)."""
