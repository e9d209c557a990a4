"""``jaka_driver_node``: the ROS adapter around a backend.

Parameters (private, ``~name``):
  ``backend``        ``sim`` (MuJoCo twin, default) or ``controller`` (JAKA TCP protocol)
  ``model``          one of ``models.MODEL_NAMES``: ``zu3`` ``zu5`` (default) ``zu7`` ``zu12``
                     ``zu18`` ``zu20`` ``zu30`` ``c5`` ``c7`` ``c12`` ``pro5`` ``pro7`` ``pro12``
                     ``pro16`` ``pro18`` ``s5`` ``s7`` ``s12`` ``a5`` ``a12`` ``a20`` ``minicobo``
  ``rate``           highest state publishing rate, Hz (default 125, the controller's cycle):
                     each sample is published once, as it comes
  ``ip``             controller address (controller backend; default 10.5.5.100)
  ``command_port``   controller command port (default 10001)
  ``status_port``    controller status port (default 10000)
  ``status_source``  ``stream`` (port 10000, default), ``request`` (port ``data_port``, as JAKA's
                     SDK reads status) or ``both``
  ``data_port``      controller data_request port (default 10004)
  ``kinematics``     controller: which chain is right when the controller's kinematic
                     parameters (get_dh_param) are another arm's than ``model``: ``auto``
                     (default: its parameters when they are a calibration of the model's,
                     every motion refused when they are another arm's), ``controller``, ``model``
  ``network_loss_action``  controller: what the controller does with the motion under way
                     once this driver's connection has been lost ``network_loss_time``:
                     ``keep``, ``pause`` or ``abort`` (default), sent at every connection
  ``network_loss_time``  controller: s (default 0.1)
  ``installation_angle``  ``[tilt_x, rot_z]`` rad: how the arm is mounted (tilt about x
                     0–π, then rotation about z 0–2π; default upright, as the arm already is),
                     set at start-up as ``~set_installation_angle`` sets it
  ``jog_timeout``    s after the last jog call before the jog stops (default 3.0)
  ``servo_timeout``  s without a servo target before the stream counts as stopped (0.1)
  ``twist_timeout``  s after the last ``~twist_command`` before the velocity jog stops (0.1)
  ``scene``          sim: workcell obstacles file (MJCF or YAML); ``""`` or ``none``
                     (default): none; a YAML scene's ``cameras:`` are rendered and published
                     (ros/camera_topics.py)
  ``wrist_camera``   sim: a camera on the flange (jaka_driver.common.camera_spec's
                     ``WRIST_CAMERA``; default false)
  ``programs``       sim: the folder of the programs the twin runs (docs/programs.md; default
                     this package's config/programs), and of its recordings (``track/``)
  ``force_sensor``   a flange force/torque sensor on the arm: ``true``, ``false``, or ``model``
                     or ``""`` (default: as config/<model>.yaml's ``force_sensor.mounted``
                     says) — the
                     twin's is mounted, a controller's arm is said to carry one
  ``conventions``    ``document`` (default: JAKA's interface document) or ``jaka_code`` (JAKA's
                     driver code, for programs written against it: RPY poses, servo
                     increments, jog speed from mvacc, tool_position a PoseStamped in mm,
                     servo_state = enabled; jaka_driver.conventions has the table)
  ``servo_increment``  servo_j/servo_p take increments as JAKA's driver code does (default
                     false: absolute targets, as the interface document says; implied by
                     ``conventions:=jaka_code``)
  ``sim_time``       sim: the twin owns time — it publishes ``/clock`` every 8 ms cycle and
                     sets ``/use_sim_time`` (before this node's rospy reads it); every stamp
                     and timeout of the driver is then sim time (default false); refused if
                     another live node already publishes ``/clock`` (ros/sim_time.py)
  ``real_time_factor``  sim_time: sim seconds per wall second (default 1.0; 0 = as fast as
                     the machine can step)
  ``realtime_priority``  SCHED_FIFO priority of the node's periodic threads (its cycle's,
                     watchers, slower topics) once it is ready (default 10; 0: the default
                     policy); needs root, CAP_SYS_NICE or an rtprio limit, else the log says
                     so; not in sim time (host/realtime.py)
  ``trajectory_action``  name of the FollowJointTrajectory action (default
                     ``~follow_joint_trajectory``; e.g. ``/jaka_zu5_controller/follow_joint_trajectory``)
  ``gripper``        the tool on the tool connector: ``none`` (default), ``dh_pgi`` (a DH-Robotics
                     gripper: the twin mounts one; on a controller the driver sets the tool
                     connector up for it) or ``suction`` (the twin's suction cup, tool DO 0)
  ``gripper_channel``, ``gripper_slave``, ``gripper_baud``, ``gripper_volts``, ``gripper_crc``
                     how the gripper hangs on the tool connector: RS485 channel (1 = RS485L,
                     default), slave id (1), baud (115200), tool supply V (24), frames with
                     their CRC (false: 6 bytes, as JAKA's demos)
  ``gripper_action`` name of the GripperCommand action (default ``~gripper/gripper_action``)

Topics: ``~tool_position``, ``~joint_position``, ``~robot_states`` and ``joint_states``, all
from one publisher thread that nothing blocks; blocking moves wait in their service threads.
``~speed_ratio``, ``~program/state`` and ``~on_limit`` (latched). Inputs: ``~joint_command``, ``~joint_position_command``,
``~twist_command``; their refusals and stops on ``~command_status``.
"""
from __future__ import annotations

import logging
import sys

import rospy

from ..common.models import MODEL_NAMES, load_model, repo_root
from ..conventions import conventions_named
from ..driver import RobotDriver
from ..host import heap, latency_hint, realtime
from . import sim_time
from .circular_move import advertise_circular_move
from .camera_topics import CameraTopics
from .command_status import CommandStatus
from .diagnostics import Diagnostics
from .force_services import advertise_force
from .tool_io_services import advertise_tool_io
from .installation import advertise_installation, apply_parameter
from .limit_state import OnLimitTopic
from .frames_tf import FrameBroadcaster
from .gripper_action import GripperActionServer, advertise_gripper_services
from .gripper_topics import GripperTopics
from .programs import advertise_programs
from .recording_services import advertise_recording
from .services import advertise
from .servo_filter import advertise_servo_filter
from .servo_topics import JointCommandInput
from .speed_ratio import SpeedRatio
from .state_publisher import DEFAULT_RATE_HZ, StatePublisher
from .trajectory_action import TrajectoryActionServer
from .twin_parts import PartsPublisher
from .twin_services import advertise_twin
from .twist_input import TwistInput


def make_backend(kind: str, model_name: str, params: dict):
    """The backend named by ``~backend``; imported lazily so the twin's MuJoCo is not loaded
    for a real controller and vice versa."""
    model = load_model(model_name)
    if kind == "sim":
        from ..programs import FolderPrograms
        from ..sim import SimBackend
        # the program engine is handed in, as a controller's parts are
        return SimBackend(model, scene=scene_param(params.get("scene", "")),
                          sim_time=bool(params.get("sim_time")),
                          real_time_factor=float(params.get("real_time_factor", 1.0)),
                          programs=FolderPrograms(params.get("programs") or None),
                          force_sensor=force_sensor_param(params.get("force_sensor", "")),
                          gripper=str(params.get("gripper") or "none"),
                          wrist_camera=bool(params.get("wrist_camera", False)))
    if kind == "controller":
        from ..controller import ControllerBackend
        return ControllerBackend(model, host=params["ip"], command_port=params["command_port"],
                                 status_port=params["status_port"],
                                 status_source=params["status_source"],
                                 data_port=params["data_port"],
                                 kinematics=params["kinematics"],
                                 force_sensor=force_sensor_param(params.get("force_sensor", "")),
                                 stall_timeout=params["stall_timeout"],
                                 network_loss_action=params["network_loss_action"],
                                 network_loss_time=params["network_loss_time"])
    raise ValueError(f"unknown backend {kind!r}; expected 'sim' or 'controller'")


def gripper_arguments(p: dict) -> dict:
    """RobotDriver's gripper arguments from the parameters: a register-map gripper driven over
    the tool connector (the suction cup is switched by a tool DO: no gripper door)."""
    from ..devices import MAPS, ConnectorSetup
    kind = p.get("gripper", "none")
    if kind not in ("none", "suction") + tuple(MAPS):
        raise ValueError(f"~gripper is {kind!r}; expected none, suction or "
                         f"{', '.join(MAPS)}")
    if kind not in MAPS:
        return {"gripper": "none"}
    return {"gripper": kind, "gripper_setup": ConnectorSetup(
        volts=p["gripper_volts"], channel=p["gripper_channel"], slave=p["gripper_slave"],
        baudrate=p["gripper_baud"], crc=p["gripper_crc"])}


def scene_param(value) -> str | None:
    """``~scene``: the workcell file, or None for none (``""`` or ``none``: the launch file's
    default is a word, since roslaunch lists an empty default as a required argument)."""
    text = str(value or "").strip()
    return None if text.lower() in ("", "none") else text


def force_sensor_param(value) -> bool | None:
    """``~force_sensor``: True / False — the arm carries a sensor or not (the twin's is
    mounted; a controller's force requests are sent); "" (or "model") as the model's
    configuration says."""
    text = str(value).strip().lower()
    if text in ("", "model"):
        return None
    if text in ("true", "1", "yes"):
        return True
    if text in ("false", "0", "no"):
        return False
    raise ValueError(f"~force_sensor is {value!r}; expected true, false or \"\" (the model's "
                     "configuration)")


NODE_NAME = "jaka_driver"

class _ToRosout(logging.Handler):
    """The backends log with ``logging`` (they know nothing of ROS); show it where ROS users
    look: rosout and the console."""

    def emit(self, record: logging.LogRecord) -> None:
        message = self.format(record)
        if record.levelno >= logging.ERROR:
            rospy.logerr(message)
        elif record.levelno >= logging.WARNING:
            rospy.logwarn(message)
        else:
            rospy.loginfo(message)


def _forward_logging() -> None:
    logger = logging.getLogger("jaka_driver")
    logger.setLevel(logging.INFO)
    logger.addHandler(_ToRosout())
    logger.propagate = False


def _params() -> dict:
    return {
        "backend": rospy.get_param("~backend", "sim"),
        "model": str(rospy.get_param("~model", "zu5")).lower(),
        "rate": float(rospy.get_param("~rate", DEFAULT_RATE_HZ)),
        "ip": rospy.get_param("~ip", rospy.get_param("ip", "10.5.5.100")),
        "command_port": int(rospy.get_param("~command_port", 10001)),
        "status_port": int(rospy.get_param("~status_port", 10000)),
        "status_source": str(rospy.get_param("~status_source", "stream")),
        "data_port": int(rospy.get_param("~data_port", 10004)),
        "stall_timeout": float(rospy.get_param("~stall_timeout", 0.5)),
        "kinematics": str(rospy.get_param("~kinematics", "auto")).lower(),
        "network_loss_action": str(rospy.get_param("~network_loss_action", "abort")),
        "network_loss_time": float(rospy.get_param("~network_loss_time", 0.1)),
        "jog_timeout": float(rospy.get_param("~jog_timeout", 3.0)),
        "servo_timeout": float(rospy.get_param("~servo_timeout", 0.1)),
        "twist_timeout": float(rospy.get_param("~twist_timeout", 0.1)),
        "scene": rospy.get_param("~scene", ""),
        "programs": str(rospy.get_param("~programs", "") or repo_root() / "config" / "programs"),
        "conventions": str(rospy.get_param("~conventions", "document")),
        "servo_increment": bool(rospy.get_param("~servo_increment", False)),
        "sim_time": bool(rospy.get_param("~sim_time", False)),
        "real_time_factor": float(rospy.get_param("~real_time_factor", 1.0)),
        "force_sensor": rospy.get_param("~force_sensor", ""),
        "gripper": str(rospy.get_param("~gripper", "none") or "none").lower(),
        "gripper_channel": int(rospy.get_param("~gripper_channel", 1)),
        "gripper_slave": int(rospy.get_param("~gripper_slave", 1)),
        "gripper_baud": int(rospy.get_param("~gripper_baud", 115200)),
        "gripper_volts": float(rospy.get_param("~gripper_volts", 24.0)),
        "gripper_crc": bool(rospy.get_param("~gripper_crc", False)),
        "wrist_camera": bool(rospy.get_param("~wrist_camera", False)),
        "installation_angle": rospy.get_param("~installation_angle", ""),
        "realtime_priority": rospy.get_param("~realtime_priority", realtime.DEFAULT_PRIORITY),
    }


def _settled(kept: int, took: float) -> None:
    rospy.loginfo(f"{kept} objects of start-up kept out of full garbage collections "
                  f"(collected in {took * 1e3:.0f} ms)")


def _realtime(p: dict) -> str:
    """Real-time priority for the node's periodic threads now that it is ready
    (host/realtime.py)."""
    if p["sim_time"] and p["realtime_priority"]:
        # At real_time_factor 0 the twin steps as fast as it can: at real-time priority it
        # would hold cores from every other program; and in sim time what a client sees is
        # stamped in sim time, whenever the wall clock lets the threads run.
        return "no real-time priority in sim time; threads at the default policy"
    return realtime.request_realtime(p["realtime_priority"])


def main() -> int:
    scheduling = latency_hint.request_short_slice()     # done already by the script
    requested = sim_time.requested(sys.argv, NODE_NAME)
    clock_owners = (sim_time.other_clock_publishers(sim_time.node_name(sys.argv, NODE_NAME))
                    if requested else [])
    if requested and not clock_owners:
        sim_time.use_sim_time()
    rospy.init_node(NODE_NAME)
    _forward_logging()
    rospy.loginfo(f"scheduling: {scheduling}")
    p = _params()
    if p["sim_time"] and p["backend"] != "sim":
        rospy.logwarn("~sim_time applies to the twin only: the controller backend runs on "
                      "the wall clock")
        p["sim_time"] = False
    if p["sim_time"]:
        if not requested:
            clock_owners = sim_time.other_clock_publishers(rospy.get_name())
        if clock_owners:
            rospy.logfatal(f"~sim_time: {', '.join(clock_owners)} already publishes "
                           f"{sim_time.CLOCK_TOPIC}; two clocks would move ROS time each their "
                           "own way. Stop it, or start this twin with sim_time:=false")
            return 2
        if not requested:
            rospy.logwarn("~sim_time was set after start-up; /use_sim_time is set now, but this "
                          "node's rospy keeps the wall clock")
            sim_time.use_sim_time()
        if p["rate"] != DEFAULT_RATE_HZ:
            rospy.logwarn(f"~rate {p['rate']:g} Hz is ignored in sim time: the twin publishes "
                          "one sample per 8 ms cycle, every cycle (a deterministic stream)")
    if not 0 < p["stall_timeout"] < float("inf"):
        rospy.logfatal(f"~stall_timeout {p['stall_timeout']} s; expected a time > 0 s")
        return 2
    if not p["real_time_factor"] >= 0:
        rospy.logfatal(f"~real_time_factor {p['real_time_factor']} is negative; expected ≥ 0 "
                       "(0 = as fast as possible)")
        return 2
    priority = p["realtime_priority"]
    why = (realtime.priority_error(priority) if isinstance(priority, int)
           and not isinstance(priority, bool) else f"realtime_priority {priority!r}; expected "
           "a whole number")
    if why is not None:
        rospy.logfatal(f"~{why}")
        return 2
    if p["model"] not in MODEL_NAMES:
        rospy.logfatal(f"unknown model {p['model']!r}; expected one of {', '.join(MODEL_NAMES)}")
        return 2
    if not 1.0 <= p["rate"] <= 1000.0:
        rospy.logfatal(f"~rate {p['rate']} Hz is outside 1–1000 Hz")
        return 2
    try:
        conventions = conventions_named(p["conventions"]).with_servo_increment(
            p["servo_increment"])
    except ValueError as exc:
        rospy.logfatal(f"~conventions: {exc}")
        return 2
    try:
        gripper_args = gripper_arguments(p)
        backend = make_backend(p["backend"], p["model"], p)
    except ValueError as exc:
        rospy.logfatal(str(exc))
        return 2
    driver = RobotDriver(backend, jog_timeout=p["jog_timeout"], servo_timeout=p["servo_timeout"],
                         conventions=conventions, twist_timeout=p["twist_timeout"],
                         **gripper_args)
    rospy.loginfo(f"conventions {conventions.describe()}")
    publisher = StatePublisher(driver, p["rate"])       # before the twin's time starts
    _settled(*heap.settle())           # before the backend's threads run (host/heap.py)
    driver.start()
    rospy.on_shutdown(driver.shutdown)
    publisher.start()
    advertise(driver)
    advertise_circular_move(driver)
    advertise_programs(driver)
    advertise_recording(driver)
    advertise_servo_filter(driver)
    advertise_installation(driver)
    why = apply_parameter(driver, p["installation_angle"])
    if why is not None:
        rospy.logfatal(why)
        driver.shutdown()
        return 2
    if driver.twin.present:             # the twin's parts, when the backend is a twin
        PartsPublisher(driver, publisher.also_publish)
    TrajectoryActionServer(driver, rospy.get_param("~trajectory_action",
                                                   "~follow_joint_trajectory"))
    FrameBroadcaster(driver)
    status = CommandStatus()
    JointCommandInput(driver, status, p["servo_timeout"])
    TwistInput(driver, status)
    advertise_twin(driver, after_reset=SpeedRatio(driver).refresh)   # ~sim/: the twin's own
    advertise_force(driver, publisher.also_publish)
    advertise_tool_io(driver, publisher.also_publish)
    if driver.gripper.absent is None:
        # the tool connector set up as the launch arguments say, before the action serves
        rospy.loginfo(f"gripper: {driver.gripper.set_up().message}")
        GripperTopics(driver, publisher.also_publish)
    advertise_gripper_services(driver)            # without a gripper: -9, how to mount one
    GripperActionServer(driver, rospy.get_param("~gripper_action", "~gripper/gripper_action"))
    OnLimitTopic(publisher.also_publish)
    Diagnostics(driver, publisher.measured_rate, extra=status.diagnostics)
    if driver.cameras.specs():
        CameraTopics(driver)
    timing = (f", sim time at real_time_factor {p['real_time_factor']:g}" if p["sim_time"]
              else "")
    _settled(*heap.settle())
    rospy.loginfo(f"scheduling: {_realtime(p)}")
    rospy.loginfo(f"jaka_driver ready: backend {p['backend']}, model {p['model']}, "
                  f"{p['rate']:g} Hz{timing}, conventions {conventions.name}")
    rospy.spin()
    return 0


if __name__ == "__main__":
    sys.exit(main())
