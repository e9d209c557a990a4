"""What the tests share, as one package (``from support.ros_harness import …``): pytest puts
``test/`` on ``sys.path`` (pytest.ini, ``pythonpath``), and ``bench/`` does the same to drive
the node through :mod:`.ros_harness`.

Real parts, started and stopped here:
  * :mod:`.ros_harness` — a rosmaster on a free port, the driver node as a subprocess, service
    proxies and topic recorders, the arm's clean slate, simulated time read from the samples;
  * :mod:`.emulated_arm` — the emulator on free ports and a RobotDriver on a ControllerBackend
    connected to it;
  * :mod:`.move_helpers` — waiting for a move a backend started, within the driver's deadline;
  * :mod:`.threads` — starting and joining a test's threads, failing when one is still alive;
  * :mod:`.twin_samples` — a twin in simulated time with every sample collected, for tests that
    read a motion sample by sample;
  * :mod:`.sensor_twin` — a twin with its flange force/torque sensor, in simulated time, for the
    force tests.

Counterparts written from the evidence, not from our code:
  * :mod:`.fake_controller` — a controller scripted from the recorded exchanges (test/data/);
  * :mod:`.jaka_sdk_model` (with :mod:`.jaka_sdk_json`, :mod:`.jaka_sdk_status`) — JAKA's SDK as
    it calls and reads; :mod:`.jaka_ros_node_model` — JAKA's ROS node on that SDK;
  * :mod:`.raw_client` — a bare JSON-over-TCP client, as a third-party client would be;
  * :mod:`.scripted_server` — a scripted TCP server for the protocol client's tests.

Shared facts: :mod:`.malformed_inputs` (how deep "deep" is, every status key read) and
:mod:`.pictures` (reading the twin's PNGs back).
"""

__all__ = ["emulated_arm", "fake_controller", "jaka_ros_node_model", "jaka_sdk_json",
           "jaka_sdk_model", "jaka_sdk_status", "malformed_inputs", "move_helpers", "pictures",
           "raw_client", "ros_harness", "scripted_server", "sensor_twin", "threads", "twin_samples"]
