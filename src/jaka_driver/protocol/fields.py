"""The names on the wire, in one table: command names, JSON keys, enum values, status fields.

Client (:mod:`.commands`, :mod:`.status_packet`) and server (the emulator) both take their
spelling from here, so a misspelt key cannot make them agree with each other and disagree with
a real controller.

Sources: what JAKA's own SDK (libjakaAPI 2.1.14) sends and reads, transcripts of public clients
recorded on a real Zu 5s (firmware 1.5.14), and several third-party clients; docs/protocol.md
lists each command with its evidence. Each command carries a ``confidence``:

* ``high``: JAKA's SDK or a transcript of a real controller shows name, fields and reply keys
  (or every client that implements the command agrees on them).
* ``medium``: name and fields agree, but units or the value format of a reply come from one
  client's doc strings only (for instance speed/accel units of ``joint_move``/``moveL``, the
  ``get_robot_state`` values, the ``jog`` speed unit).
* ``low``: seen in one client only; may not exist on every controller version.

Confirm the medium and low entries against a real controller before relying on them.
"""
from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from types import MappingProxyType
from typing import Mapping, Tuple

#: TCP ports of the controller.
COMMAND_PORT = 10001
STATUS_PORT = 10000           # pushes a status packet every 8 ms
STATUS_REQUEST_PORT = 10004   # answers {"cmdName":"data_request"} with one zlib-compressed packet
#: The SDK reads a 10004 reply into a buffer of this many bytes: a compressed reply must fit.
DATA_REQUEST_MAX_BYTES = 8200

#: ``errorCode`` of a successful reply (a string on the wire). Other codes seen: "1" (exception)
#: and "2" (error, e.g. ``"call joint_move failed"`` or a program that does not exist).
ERROR_CODE_OK = "0"
ERROR_CODE_EXCEPTION = "1"
ERROR_CODE_FAILED = "2"


class Field:
    """JSON keys of command requests and replies."""

    CMD_NAME = "cmdName"
    ERROR_CODE = "errorCode"
    ERROR_MSG = "errorMsg"

    JOINT_POSITION = "jointPosition"      # [6] deg
    CART_POSITION = "cartPosition"        # [6] mm / deg RPY
    SERVO_CART_POSITION = "catPosition"   # [6] mm / deg RPY; "cat" is the protocol's spelling
    SPEED = "speed"
    ACCEL = "accel"
    REL_FLAG = "relFlag"                  # 0 absolute, 1 relative
    TOL = "tol"
    STEP_NUM = "stepNum"                  # servo period = stepNum × 8 ms

    JOG_MODE = "jog_mode"
    COORD_MAP = "coord_map"
    JNUM = "jnum"
    JOGVEL = "jogvel"
    POSCMD = "poscmd"

    FILTER_TYPE = "filter_type"
    LPF_CF = "lpf_cf"                     # Hz
    RATE_VALUE = "rate_value"             # 0..1

    ENABLE = "enable"
    POWER = "power"
    EMERGENCY_STOP = "emergency_stop"
    PROTECTIVE_STOP = "protective_stop"
    IN_SERVOMOVE = "in_servomove"
    DRAG_STATUS = "drag_status"
    JOINT_POS = "joint_pos"               # [6] deg
    TCP_POS = "tcp_pos"                   # [6] mm / deg RPY

    TOOL_OFFSET = "tooloffset"            # [6] mm / deg RPY
    USER_OFFSET = "userffset"             # [6] mm / deg RPY; JAKA's SDK spells it so (sic)
    ID = "id"
    NAME = "name"
    TOOL_ID = "tool_id"
    USER_FRAME_ID = "user_frame_id"
    MASS = "mass"                         # kg
    CENTROID = "centroid"                 # [3] mm
    SENSITIVITY_VAL = "sensitivityVal"    # 0 off, 1..5
    SENSITIVITY_LEVEL = "sensitivityLevel"

    IO_TYPE = "type"
    INDEX = "index"                       # 1-based on the wire (the SDK sends API index + 1)
    VALUE = "value"
    DIN_STATUS = "din_status"
    VERSION = "version"

    # get_motion_state
    INPOS = "inpos"                       # bool: the queue is done and the arm is still
    QUEUE = "queue"                       # moves waiting in the queue
    ACTIVE_QUEUE = "active_queue"
    QUEUE_FULL = "queue_full"
    ERR_ADD_LINE = "err_add_line"
    MOTION_LINE = "motion_line"
    ON_LIMIT = "on_limit"
    STATUS = "status"                     # get_drag_status: bool
    TOOL_OFFSETS = "tool_offsets"         # get_tool_offsets: [6] mm / deg RPY
    USER_OFFSETS = "user_offsets"         # get_user_offsets: [6] mm / deg RPY
    END_POSITION = "endPosition"          # end_move: [6] mm / deg RPY
    ENABLE_FLAG = "enable_flag"           # torque_control_enable
    ANGLE_X = "angleX"                    # set_installation_angle, deg
    ANGLE_Z = "angleZ"
    INSTALLATION_ANGLE = "installation_angle"   # get_installation_angle: [[s, x, y, z],
                                                # [rx, ry, rz deg]]
    MOT_TYPE = "motType"                  # set_network_exception_handle: NetworkLossAction
    TIME_LIMIT = "timeLimit"              # set_network_exception_handle: ms
    PROGRAM_NAME = "programName"
    PROGRAM_STATE = "programState"        # a string: see ProgramState
    CURRENT_LINE = "current_line"         # get_current_line: int
    VAR_LIST = "var_list"                 # query_user_defined_variable: [{id, value, alias}]
    ID_NEW = "id_new"                     # modify_user_defined_variable
    VALUE_NEW = "value_new"
    ALIAS_NEW = "alias_new"
    DH_PARAM = "dh_param"                 # get_dh_param: 4 rows of 6: alpha deg, a mm, d mm,
                                          # joint_homeoff deg
    TIO_VOUT_ENA = "tio_vout_ena"         # get/set_tio_vout_param: 0/1
    TIO_VOUT_VOL = "tio_vout_vol"         # voltage code
    # the tool connector (TIO) and its RS485 channels, as JAKA's SDK spells them
    PIN_TYPE = "pinType"                  # set/get_tio_pin_mode: 0 DI, 1 DO, 2 AI
    PIN_MODE = "pinMode"
    CHN_ID = "chnId"                      # set/get_rs485_chn_mode
    CHN_MODE = "chnMode"                  # 0 Modbus RTU, 1 raw RS485, 2 torque sensor
    CHN_ID_COMM = "chn_id"                # set/get_rs485_chn_comm, send_tio_rs_command
    SLAVE_ID = "slaveId"
    BAUDRATE = "baudrate"
    DATABIT = "databit"
    STOPBIT = "stopbit"
    PARITY = "parity"                     # 78 'N', 79 'O', 69 'E'
    CMD_BUF = "cmdBuf"                    # send_tio_rs_command: the frame's bytes
    SIGNAL_NAME = "tio_signal_name"       # add/del_tio_rs_signal
    SIGNAL_CHN_ID = "tio_signal_chnId"
    SIGNAL_SIG_TYPE = "tio_signal_sigType"
    SIGNAL_SIG_ADDR = "tio_signal_sigAddr"
    FREQUENCY = "frequency"               # Hz
    SIGNALS = "signals"                   # get_tio_signals: [[name, chn, type, addr, value, Hz]]
    ORI_VEL = "ori_vel"                   # moveL orientation speed, deg/s
    ORI_ACC = "ori_acc"                   # moveL orientation acceleration, deg/s²
    EXECUTING_LINE_ID = "executing_line_id"   # the SDK adds it to every move; ignored
    SDK_VERSION = "sdk_version"           # get_version request, the SDK's own version
    # get_version reply: the controller's identity, every one a string (a number here aborts
    # the login of JAKA's SDK)
    CONTROLLER_ID = "controller_id"
    CONTROLLER_GUARANTEE = "controller_guarantee"
    ROBOT_ID = "robot_id"
    ROBOT_NAME = "robot_name"
    SCB_VERSION = "scb_version"
    SERVO_VERSION = "servo_version"
    # set_servo_move_filter, by filter_type (values unconverted: Hz, deg/s…, mm/s…)
    NLF_MAX_VR = "nlf_max_vr"
    NLF_MAX_AR = "nlf_max_ar"
    NLF_MAX_JR = "nlf_max_jr"
    NLF_MAX_VP = "nlf_max_vp"
    NLF_MAX_AP = "nlf_max_ap"
    NLF_MAX_JP = "nlf_max_jp"
    MMF_MAX_BUF = "mmf_max_buf"
    MMF_KP = "mmf_kp"
    MMF_KV = "mmf_kv"
    MMF_KA = "mmf_ka"
    # movc (circular move)
    POS_END = "pos_end"                   # [6] mm / deg RPY
    POS_MID = "pos_mid"                   # [6] mm / deg RPY
    CIRCLE_CNT = "circle_cnt"             # a double: extra turns
    CIRCLE_MODE = "circle_mode"           # an int 0–3: the attitude rule
    # the torque sensor and force control (JAKA's SDK 2.1.14, its spellings kept)
    SENSOR_BRAND = "sensor_brand"
    SENSOR_MODE = "sensor_mode"               # 1 on, 0 off
    AXIS = "axis"                             # 0..5: x y z rx ry rz
    OPT = "opt"                               # 0/1: the axis is enabled
    FT_USER = "ftUser"
    FT_CONSTANT = "ftConstant"
    FT_NORMAL_TRACK = "ftNnormalTrack"        # (sic, two n)
    FT_REBOUND = "ftReboundFK"
    ADMIT_CONFIG = "admitConfig"              # get: 6 rows [opt, ft_user, ft_rebound,
    # ft_constant, ft_normal_track]
    IDENTIFY_STATUS = "identify_status"       # 0 done, 1 running, 2 error
    REBOUND = "rebound"
    RIGIDITY = "rigidity"
    FORCE_CTRL_CONFIG = "force_ctrl_config"   # get_tool_drive_config: 6 rows [opt, rigidity,
    # rebound]
    SENSOR_COMPENSATION = "sensor_compensation"
    COMPLIANCE_TYPE = "compliance_type"       # 0 none, 1 constant force, 2 velocity
    COMM_TYPE = "type"                        # set/get_torque_sensor_comm; also the reading
    # type of get_torque_sensor_data (1 actual, 2 general, 3 real)
    IP_ADDR = "ip_addr"
    PORT = "port"
    SENSOR_FILTER = "torqueSensorFilter"
    SENSOR_SOFT_LIMIT = "torqueSensorSoftLimit"   # {Fx, Fy, Fz, Mx, My, Mz}
    COMPLIANT_CTRL = "compliant_ctrl"         # [vc_level, rate1, rate2, rate3, rate4]
    COMPLIANT_CONDITION = "compliant_condition"   # [6]
    FT_FRAME = "ftFrame"                      # 0 tool, 1 world
    SENSOR_DATA_STATUS = "status"
    SENSOR_ERRCODE = "errcode"
    SENSOR_DATA = "data"                      # [6] N, N·m
    DRIVE_STAT = "drive_stat"
    TOOL_DRAG_FRAME = "toolDragFrame"         # 0 tool, 1 world
    SENSITIVITY_LEVEL_FUSION = "sensitivity_level"
    RANGE_LEVEL = "range_level"
    SPEED_LIMIT = "speed_limit"
    ANGULAR_SPEED_LIMIT = "angular_speed_limit"
    REF_POINT = "ref_point"
    THRESHOLD_PERCENT = "threshold_percent"   # [6]
    # trajectory recording (JAKA's SDK 2.1.14, sdk §11 in docs/protocol.md)
    XYZ_INTERVAL = "xyz_interval"             # mm, 2 decimals on the wire
    RPY_INTERVAL = "rpy_interval"             # deg, 2 decimals on the wire
    TRAJ_VEL = "vel"                          # mm/s, the replay's speed
    TRAJ_ACC = "acc"                          # mm/s², the replay's acceleration
    TRAJ_FILENAME = "filename"                # set_traj_sample_mode (lower case)
    TRAJ_MODE = "mode"                        # 1 start, 0 stop
    SAMPLE_STATUS = "sampleStatus"            # an int: 1 recording
    TRAJ_FILE_NAMES = "trajTrackFileName"     # a list of strings
    TRAJ_SRC = "src"
    TRAJ_DEST = "dest"
    TRAJ_FILE_NAME = "fileName"               # generate / remove (camel case)

#: The keys of ``torqueSensorSoftLimit``, in the order of a wrench.
SOFT_LIMIT_KEYS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")

#: The ``get_version`` identity keys JAKA's SDK reads at login, all strings.
IDENTITY_FIELDS = (Field.VERSION, Field.CONTROLLER_ID, Field.CONTROLLER_GUARANTEE,
                   Field.ROBOT_ID, Field.ROBOT_NAME, Field.SCB_VERSION, Field.SERVO_VERSION)


class Cmd:
    """``cmdName`` values."""

    POWER_ON = "power_on"
    POWER_OFF = "power_off"
    ENABLE_ROBOT = "enable_robot"
    DISABLE_ROBOT = "disable_robot"
    GET_ROBOT_STATE = "get_robot_state"
    EMERGENCY_STOP_STATUS = "emergency_stop_status"
    PROTECTIVE_STOP_STATUS = "protective_stop_status"
    CLEAR_ERROR = "clear_error"
    JOINT_MOVE = "joint_move"
    MOVE_L = "moveL"
    JOG = "jog"
    STOP_PROGRAM = "stop_program"
    SERVO_MOVE = "servo_move"
    IS_IN_SERVOMOVE = "is_in_servomove"
    SERVO_J = "servo_j"
    SERVO_P = "servo_p"
    SET_SERVO_MOVE_FILTER = "set_servo_move_filter"
    RAPID_RATE = "rapid_rate"
    GET_JOINT_POS = "get_joint_pos"
    GET_TCP_POS = "get_tcp_pos"
    GET_DATA = "get_data"
    KINE_FORWARD = "kine_forward"
    KINE_INVERSE = "kine_inverse"
    SET_TOOL_OFFSETS = "set_tool_offsets"
    SET_TOOL_ID = "set_tool_id"
    GET_CURR_TOOL_ID = "get_curr_tool_id"
    SET_USER_OFFSETS = "set_user_offsets"
    SET_USER_ID = "set_user_id"
    GET_CURR_USER_ID = "get_curr_user_id"
    SET_PAYLOAD = "set_payload"
    GET_PAYLOAD = "get_payload"
    SET_CLSN_SENSITIVITY = "set_clsn_sensitivity"
    GET_CLSN_SENSITIVITY = "get_clsn_sensitivity"
    SET_DIGITAL_OUTPUT = "set_digital_output"
    SET_ANALOG_OUTPUT = "set_analog_output"
    GET_DIGITAL_INPUT = "get_digital_input"
    GET_DIGITAL_INPUT_STATUS = "get_digital_input_status"
    GET_ANALOG_OUTPUT = "get_analog_output"
    DRAG_STATUS = "drag_status"
    GET_VERSION = "get_version"
    QUIT = "quit"
    GET_MOTION_STATE = "get_motion_state"
    WAIT_COMPLETE = "wait_complete"
    END_MOVE = "end_move"
    IS_ON_LIMIT = "is_on_limit"
    GET_DIGITAL_OUTPUT = "get_digital_output"
    GET_ANALOG_INPUT = "get_analog_input"
    GET_RAPID_RATE = "get_rapid_rate"
    GET_TOOL_OFFSETS = "get_tool_offsets"
    GET_USER_OFFSETS = "get_user_offsets"
    GET_DRAG_STATUS = "get_drag_status"
    TORQUE_CONTROL_ENABLE = "torque_control_enable"
    GET_PROGRAM_STATE = "get_program_state"
    SET_INSTALLATION_ANGLE = "set_installation_angle"
    GET_INSTALLATION_ANGLE = "get_installation_angle"
    SET_NETWORK_EXCEPTION_HANDLE = "set_network_exception_handle"
    LOAD_PROGRAM = "load_program"
    PLAY_PROGRAM = "play_program"
    PAUSE_PROGRAM = "pause_program"
    RESUME_PROGRAM = "resume_program"
    GET_LOADED_PROGRAM = "get_loaded_program"
    GET_EXIST_PROGRAMS = "get_exist_programs"
    TORQUE_FEEDFORWARD = "torque_feedforward"
    GET_EXTIO_STATUS = "get_extio_status"
    GET_FUNCDI_STATUS = "get_funcdi_status"
    QUERY_USER_DEFINED_VARIABLE = "query_user_defined_variable"
    MODIFY_USER_DEFINED_VARIABLE = "modify_user_defined_variable"
    SET_TIO_VOUT_PARAM = "set_tio_vout_param"
    GET_TIO_VOUT_PARAM = "get_tio_vout_param"
    SET_TIO_PIN_MODE = "set_tio_pin_mode"
    GET_TIO_PIN_MODE = "get_tio_pin_mode"
    SET_RS485_CHN_MODE = "set_rs485_chn_mode"
    GET_RS485_CHN_MODE = "get_rs485_chn_mode"
    SET_RS485_CHN_COMM = "set_rs485_chn_comm"
    GET_RS485_CHN_COMM = "get_rs485_chn_comm"
    ADD_TIO_RS_SIGNAL = "add_tio_rs_signal"
    DEL_TIO_RS_SIGNAL = "del_tio_rs_signal"
    SEND_TIO_RS_COMMAND = "send_tio_rs_command"
    GET_TIO_SIGNALS = "get_tio_signals"
    GET_CURRENT_LINE = "get_current_line"
    GET_DH_PARAM = "get_dh_param"
    MOVC = "movc"                         # circular move
    SET_TOOL_PAYLOAD = "set_tool_payload"   # the torque sensor's tool payload
    GET_TOOL_PAYLOAD = "get_tool_payload"
    # the torque sensor and force control, as JAKA's SDK spells them (sic: "torsenosr",
    # "staus", "stat")
    SET_TORSENOSR_BRAND = "set_torsenosr_brand"
    GET_TORSENOSR_BRAND = "get_torsenosr_brand"
    SET_TORQUE_SENSOR_MODE = "set_torque_sensor_mode"
    SET_ADMIT_CTRL_CONFIG = "set_admit_ctrl_config"
    GET_ADMIT_CTRL_CONFIG = "get_admit_ctrl_config"
    START_TORQ_SENSOR_PAYLOAD_IDENTIFY = "start_torq_sensor_payload_identify"
    GET_TORQ_SENSOR_IDENTIFY_STAUS = "get_torq_sensor_identify_staus"
    GET_TORQ_SENSOR_PAYLOAD_IDENTIFY_RESULT = "get_torq_sensor_payload_identify_result"
    ENABLE_ADMITTANCE_CTRL = "enable_admittance_ctrl"
    DISABLE_FORCE_CONTROL = "disable_force_control"
    ZERO_END_SENSOR = "zero_end_sensor"
    SET_TOOL_DRIVE_CONFIG = "set_tool_drive_config"
    GET_TOOL_DRIVE_CONFIG = "get_tool_drive_config"
    SET_COMPLIANT_TYPE = "set_compliant_type"
    GET_COMPLIANT_TYPE = "get_compliant_type"
    SET_TORQUE_SENSOR_COMM = "set_torque_sensor_comm"
    GET_TORQUE_SENSOR_COMM = "get_torque_sensor_comm"
    SET_TORQUE_SENSOR_FILTER = "set_torque_sensor_filter"
    GET_TORQUE_SENSOR_FILTER = "get_torque_sensor_filter"
    SET_TORQUE_SENSOR_SOFT_LIMIT = "set_torque_sensor_soft_limit"
    GET_TORQUE_SENSOR_SOFT_LIMIT = "get_torque_sensor_soft_limit"
    SET_VEL_COMPLIANT_CTRL = "set_vel_compliant_ctrl"
    SET_COMPLIANCE_CONDITION = "set_compliance_condition"
    SET_FT_CTRL_FRAME = "set_ft_ctrl_frame"
    GET_FT_CTRL_FRAME = "get_ft_ctrl_frame"
    GET_TORQUE_SENSOR_DATA = "get_torque_sensor_data"
    GET_TOOL_DRIVE_STAT = "get_tool_drive_stat"
    SET_TOOL_DRIVE_FRAME = "set_tool_drive_frame"
    GET_TOOL_DRIVE_FRAME = "get_tool_drive_frame"
    SET_FUSION_DRIVE_SENSITIVITY_LEVEL = "set_fusion_drive_sensitivity_level"
    GET_FUSION_DRIVE_SENSITIVITY_LEVEL = "get_fusion_drive_sensitivity_level"
    SET_MOTION_LIMIT_WARNING_RANGE = "set_motion_limit_warning_range"
    GET_MOTION_LIMIT_WARNING_RANGE = "get_motion_limit_warning_range"
    SET_COMPLIANT_SPEED_LIMIT = "set_compliant_speed_limit"
    GET_COMPLIANT_SPEED_LIMIT = "get_compliant_speed_limit"
    SET_TORQUE_REF_POINT = "set_torque_ref_point"
    GET_TORQUE_REF_POINT = "get_torque_ref_point"
    SET_END_SENSOR_SENSITIVITY_THRESHOLD = "set_end_sensor_sensitivity_threshold"
    GET_END_SENSOR_SENSITIVITY_THRESHOLD = "get_end_sensor_sensitivity_threshold"
    # trajectory recording
    SET_TRAJ_CONFIG = "set_traj_config"
    GET_TRAJ_CONFIG = "get_traj_config"
    SET_TRAJ_SAMPLE_MODE = "set_traj_sample_mode"
    GET_TRAJ_SAMPLE_STATUS = "get_traj_sample_status"
    GET_EXIST_TRAJ_FILE_NAME = "get_exist_traj_file_name"
    RENAME_TRAJ_FILE_NAME = "rename_traj_file_name"
    REMOVE_TRAJ_FILE = "remove_traj_file"
    GENERATE_TRAJ_EXE_FILE = "generate_traj_exe_file"
    DATA_REQUEST = "data_request"         # port 10004 only


class JogMode(IntEnum):
    """``jog_mode`` of the ``jog`` command."""
    STOP = 0
    CONTINUOUS = 1
    INCREMENT = 2
    ABSOLUTE = 3


class CoordMap(IntEnum):
    """``coord_map`` of ``jog``. Note: the official ROS jog service numbers 0 joint, 1 base;
    the wire numbers 0 base, 1 joint (docs/protocol.md, "Jog")."""
    BASE = 0
    JOINT = 1
    TOOL = 2


class IOType(IntEnum):
    """``type`` of the IO commands, as JAKA's SDK numbers them. The status packet carries
    3 in ``relay_io`` (outputs, cabinet CAB V3 only) and 4–6 in ``mb_slave_*``, ``pn_dev_*``,
    ``eip_adpt_*``."""
    CABINET = 0
    TOOL = 1
    EXTEND = 2            # extension IO (Modbus master)
    RELAY = 3
    MODBUS_SLAVE = 4
    PROFINET_SLAVE = 5
    EIP_SLAVE = 6


class ServoFilter(IntEnum):
    """``filter_type`` of ``set_servo_move_filter`` (JAKA's SDK's six)."""
    NONE = 0
    JOINT_LPF = 1
    JOINT_NLF = 2
    JOINT_MMF = 3
    CARTE_NLF = 4
    SPEED_FORESIGHT = 5


class ProgramState:
    """``programState`` of ``get_program_state``: a **string** on the wire (JAKA's SDK compares
    strings and aborts on a number)."""
    IDLE = "idle"
    RUNNING = "running"
    PAUSED = "paused"


class TaskState(IntEnum):
    """``task_state`` of the status stream (medium confidence: two third-party sources)."""
    UNKNOWN = 0
    POWER_OFF = 1
    POWER_ON = 2
    DISABLED = 3
    ENABLED = 4


class InterpState(IntEnum):
    """``interp_state`` of the status stream (medium confidence)."""
    IDLE = 0
    LOADING = 1
    PAUSED = 2
    RUNNING = 3


@dataclass(frozen=True)
class CommandSpec:
    """One row of the command table: the request keys a client may send (besides ``cmdName``),
    the reply keys it reads (besides ``cmdName``/``errorCode``/``errorMsg``), and how sure we
    are (see the module docstring)."""

    name: str
    request: Tuple[str, ...] = ()
    reply: Tuple[str, ...] = ()
    confidence: str = "high"
    note: str = ""


F = Field
_SPECS = (
    CommandSpec(Cmd.POWER_ON), CommandSpec(Cmd.POWER_OFF),
    CommandSpec(Cmd.ENABLE_ROBOT), CommandSpec(Cmd.DISABLE_ROBOT),
    CommandSpec(Cmd.GET_ROBOT_STATE, reply=(F.ENABLE, F.POWER), confidence="medium",
                note='values "robot_enabled"/"powered_on" per one client, 1/"1" per another'),
    CommandSpec(Cmd.EMERGENCY_STOP_STATUS, reply=(F.EMERGENCY_STOP,), confidence="medium"),
    CommandSpec(Cmd.PROTECTIVE_STOP_STATUS, reply=(F.PROTECTIVE_STOP,), confidence="medium"),
    CommandSpec(Cmd.CLEAR_ERROR),
    CommandSpec(Cmd.JOINT_MOVE, request=(F.JOINT_POSITION, F.SPEED, F.ACCEL, F.REL_FLAG),
                confidence="medium", note="speed deg/s, accel deg/s² per client doc strings; "
                "reply comes when the motion is accepted, not when it ends"),
    CommandSpec(Cmd.MOVE_L, request=(F.CART_POSITION, F.SPEED, F.ACCEL, F.REL_FLAG, F.TOL,
                                     F.ORI_VEL, F.ORI_ACC),
                confidence="medium", note='some clients spell it "move_l"; speed mm/s, accel '
                "mm/s²; tol optional; ori_vel deg/s, ori_acc deg/s² as JAKA's SDK sends them"),
    CommandSpec(Cmd.JOG, request=(F.JOG_MODE, F.COORD_MAP, F.JNUM, F.JOGVEL, F.POSCMD),
                confidence="medium", note="jogvel deg/s or mm/s, poscmd deg or mm (inferred "
                "from the deg/mm rule of the protocol)"),
    CommandSpec(Cmd.STOP_PROGRAM),
    CommandSpec(Cmd.SERVO_MOVE, request=(F.REL_FLAG,), note="relFlag 1 enter, 0 leave"),
    CommandSpec(Cmd.IS_IN_SERVOMOVE, reply=(F.IN_SERVOMOVE,), confidence="medium"),
    CommandSpec(Cmd.SERVO_J, request=(F.JOINT_POSITION, F.REL_FLAG, F.STEP_NUM),
                note="stepNum optional; refused above 180°/s implied joint speed"),
    CommandSpec(Cmd.SERVO_P, request=(F.SERVO_CART_POSITION, F.REL_FLAG, F.STEP_NUM),
                note='key "catPosition" (sic)'),
    CommandSpec(Cmd.SET_SERVO_MOVE_FILTER,
                request=(F.FILTER_TYPE, F.LPF_CF, F.NLF_MAX_VR, F.NLF_MAX_AR, F.NLF_MAX_JR,
                         F.NLF_MAX_VP, F.NLF_MAX_AP, F.NLF_MAX_JP, F.MMF_MAX_BUF, F.MMF_KP,
                         F.MMF_KV, F.MMF_KA),
                note="the keys of its filter_type only (JAKA's SDK); values in the header's "
                "units, unconverted; only while not in servo mode"),
    CommandSpec(Cmd.MOVC, request=(F.ACCEL, F.CIRCLE_CNT, F.CIRCLE_MODE, F.EXECUTING_LINE_ID,
                                   F.POS_END, F.POS_MID, F.REL_FLAG, F.SPEED, F.TOL),
                note="keys sorted as JAKA's SDK writes them; speed mm/s and accel mm/s² sent "
                "unconverted (moveL's units: the header says rad/s, no controller reply on "
                "record says which)"),
    CommandSpec(Cmd.LOAD_PROGRAM, request=(F.PROGRAM_NAME,),
                note='JAKA\'s SDK appends ".jks" to every name'),
    CommandSpec(Cmd.GET_LOADED_PROGRAM, reply=(F.PROGRAM_NAME,)),
    CommandSpec(Cmd.PLAY_PROGRAM), CommandSpec(Cmd.PAUSE_PROGRAM),
    CommandSpec(Cmd.RESUME_PROGRAM),
    CommandSpec(Cmd.GET_PROGRAM_STATE, reply=(F.PROGRAM_STATE,),
                note='a string: "idle", "running", "paused"'),
    CommandSpec(Cmd.GET_CURRENT_LINE, reply=(F.CURRENT_LINE,)),
    CommandSpec(Cmd.QUERY_USER_DEFINED_VARIABLE, reply=(F.VAR_LIST,),
                note="[{id int, value double, alias string}]; JAKA's SDK reads at most 100"),
    CommandSpec(Cmd.MODIFY_USER_DEFINED_VARIABLE, request=(F.ALIAS_NEW, F.ID_NEW, F.VALUE_NEW)),
    CommandSpec(Cmd.RAPID_RATE, request=(F.RATE_VALUE,), confidence="medium"),
    CommandSpec(Cmd.GET_JOINT_POS, reply=(F.JOINT_POS,)),
    CommandSpec(Cmd.GET_TCP_POS, reply=(F.TCP_POS,)),
    CommandSpec(Cmd.GET_DATA, note="reply carries the status-stream fields (see STATUS_FIELDS)"),
    CommandSpec(Cmd.KINE_FORWARD, request=(F.JOINT_POSITION,), reply=(F.CART_POSITION,),
                confidence="medium"),
    CommandSpec(Cmd.KINE_INVERSE, request=(F.JOINT_POSITION, F.CART_POSITION),
                reply=(F.JOINT_POSITION,), confidence="medium",
                note="request jointPosition is the reference (seed) configuration"),
    CommandSpec(Cmd.SET_TOOL_OFFSETS, request=(F.TOOL_OFFSET, F.ID, F.NAME),
                confidence="medium"),
    CommandSpec(Cmd.SET_TOOL_ID, request=(F.TOOL_ID,), confidence="medium"),
    CommandSpec(Cmd.GET_CURR_TOOL_ID, reply=(F.ID,), confidence="low"),
    CommandSpec(Cmd.SET_USER_OFFSETS, request=(F.USER_OFFSET, F.ID, F.NAME),
                note='key "userffset" (sic), as JAKA\'s SDK sends it'),
    CommandSpec(Cmd.SET_USER_ID, request=(F.USER_FRAME_ID,), confidence="medium"),
    CommandSpec(Cmd.GET_CURR_USER_ID, reply=(F.ID,), confidence="low"),
    CommandSpec(Cmd.SET_PAYLOAD, request=(F.MASS, F.CENTROID), confidence="medium",
                note='one client uses "set_tool_payload" with the same fields'),
    CommandSpec(Cmd.GET_PAYLOAD, reply=(F.MASS, F.CENTROID), confidence="medium"),
    CommandSpec(Cmd.SET_CLSN_SENSITIVITY, request=(F.SENSITIVITY_VAL,), confidence="medium"),
    CommandSpec(Cmd.GET_CLSN_SENSITIVITY, reply=(F.SENSITIVITY_LEVEL, F.SENSITIVITY_VAL),
                confidence="low", note="clients disagree on the reply key; read either"),
    CommandSpec(Cmd.SET_DIGITAL_OUTPUT, request=(F.IO_TYPE, F.INDEX, F.VALUE),
                note="index 1-based on the wire"),
    CommandSpec(Cmd.SET_ANALOG_OUTPUT, request=(F.IO_TYPE, F.INDEX, F.VALUE),
                note="index 1-based on the wire"),
    CommandSpec(Cmd.GET_DIGITAL_INPUT, request=(F.IO_TYPE, F.INDEX), reply=(F.VALUE,),
                confidence="low"),
    CommandSpec(Cmd.GET_DIGITAL_INPUT_STATUS, reply=(F.DIN_STATUS,), confidence="medium"),
    CommandSpec(Cmd.GET_ANALOG_OUTPUT, request=(F.IO_TYPE, F.INDEX), reply=(F.VALUE,),
                confidence="low"),
    CommandSpec(Cmd.GET_DIGITAL_OUTPUT, request=(F.IO_TYPE, F.INDEX), reply=(F.VALUE,)),
    CommandSpec(Cmd.GET_ANALOG_INPUT, request=(F.IO_TYPE, F.INDEX), reply=(F.VALUE,)),
    CommandSpec(Cmd.GET_MOTION_STATE, reply=(F.INPOS, F.QUEUE, F.ACTIVE_QUEUE, F.QUEUE_FULL,
                                             F.ERR_ADD_LINE, F.MOTION_LINE),
                note="the motion queue; inpos is a JSON bool"),
    CommandSpec(Cmd.WAIT_COMPLETE, note="answered once the motion queue is done"),
    CommandSpec(Cmd.END_MOVE, request=(F.END_POSITION, F.SPEED, F.ACCEL),
                note="joint-interpolated move to a Cartesian pose; speed deg/s, accel deg/s²"),
    CommandSpec(Cmd.IS_ON_LIMIT, reply=(F.ON_LIMIT,)),
    # measured from JAKA's SDK 2.1.14 (docs/protocol.md, "Network loss, mounting"): every
    # reply's errorCode a string
    CommandSpec(Cmd.SET_NETWORK_EXCEPTION_HANDLE, request=(F.MOT_TYPE, F.TIME_LIMIT),
                note="motType 0 keep, 1 pause, 2 abort the motion when the client's "
                "connection has been lost timeLimit ms"),
    CommandSpec(Cmd.SET_INSTALLATION_ANGLE, request=(F.ANGLE_X, F.ANGLE_Z),
                note="deg, 16 significant digits; tilt about x, then rotation about z"),
    CommandSpec(Cmd.GET_INSTALLATION_ANGLE, reply=(F.INSTALLATION_ANGLE,),
                note="[[s, x, y, z], [rx, ry, rz deg]]: the quaternion, then RPY"),
    CommandSpec(Cmd.GET_DRAG_STATUS, reply=(F.STATUS,), note="status is a JSON bool"),
    CommandSpec(Cmd.GET_RAPID_RATE, reply=(F.VALUE,)),
    CommandSpec(Cmd.GET_TOOL_OFFSETS, reply=(F.TOOL_OFFSETS,),
                note="a table, row = tool id (11 rows, ids 0-10), each mm + RPY deg"),
    CommandSpec(Cmd.GET_USER_OFFSETS, reply=(F.USER_OFFSETS,),
                note="a table, row = user frame id (11 rows, ids 0-10), each mm + RPY deg"),
    CommandSpec(Cmd.TORQUE_CONTROL_ENABLE, request=(F.ENABLE_FLAG,),
                note="drag mode on (1) / off (0); JAKA's SDK confirms with get_drag_status"),
    CommandSpec(Cmd.GET_DH_PARAM, reply=(F.DH_PARAM,),
                note="4 rows of 6: alpha deg, a mm, d mm, joint_homeoff deg"),
    CommandSpec(Cmd.DATA_REQUEST, note="port 10004; the reply is one zlib-compressed status "
                "packet"),
    CommandSpec(Cmd.DRAG_STATUS, reply=(F.DRAG_STATUS,), confidence="medium"),
    CommandSpec(Cmd.GET_VERSION, reply=IDENTITY_FIELDS,
                note="every identity key a string; older controllers send only version"),
    CommandSpec(Cmd.QUIT, note="the controller closes this connection"),
    # the torque sensor and force control: requests as JAKA's SDK 2.1.14 sends them, replies
    # as it reads them (SDK); how a controller acts on them is not on record
    CommandSpec(Cmd.SET_TOOL_PAYLOAD, request=(F.CENTROID, F.MASS),
                note="the torque sensor's tool payload; the SDK polls get_tool_payload"),
    CommandSpec(Cmd.GET_TOOL_PAYLOAD, reply=(F.MASS, F.CENTROID)),
    CommandSpec(Cmd.SET_TORSENOSR_BRAND, request=(F.SENSOR_BRAND,), note='(sic) "torsenosr"'),
    CommandSpec(Cmd.GET_TORSENOSR_BRAND, reply=(F.SENSOR_BRAND,)),
    CommandSpec(Cmd.SET_TORQUE_SENSOR_MODE, request=(F.SENSOR_MODE,),
                note="no get: the sensor's state is the status packet's torqsensor"),
    CommandSpec(Cmd.SET_ADMIT_CTRL_CONFIG, request=(F.AXIS, F.FT_CONSTANT, F.FT_NORMAL_TRACK,
                                                   F.FT_REBOUND, F.FT_USER, F.OPT),
                note='"ftNnormalTrack" (sic)'),
    CommandSpec(Cmd.GET_ADMIT_CTRL_CONFIG, reply=(F.ADMIT_CONFIG,),
                note="6 rows, row = axis: [opt, ft_user, ft_rebound, ft_constant, "
                "ft_normal_track]"),
    CommandSpec(Cmd.START_TORQ_SENSOR_PAYLOAD_IDENTIFY, request=(F.JOINT_POSITION,),
                note="the end pose, deg"),
    CommandSpec(Cmd.GET_TORQ_SENSOR_IDENTIFY_STAUS, reply=(F.IDENTIFY_STATUS,),
                note='(sic) "staus"; 0 done, 1 running, 2 error'),
    CommandSpec(Cmd.GET_TORQ_SENSOR_PAYLOAD_IDENTIFY_RESULT, reply=(F.MASS, F.CENTROID)),
    CommandSpec(Cmd.ENABLE_ADMITTANCE_CTRL, request=(F.ENABLE_FLAG,),
                note="enable_tool_drive sends this same command"),
    CommandSpec(Cmd.DISABLE_FORCE_CONTROL), CommandSpec(Cmd.ZERO_END_SENSOR),
    CommandSpec(Cmd.SET_TOOL_DRIVE_CONFIG, request=(F.AXIS, F.OPT, F.REBOUND, F.RIGIDITY)),
    CommandSpec(Cmd.GET_TOOL_DRIVE_CONFIG, reply=(F.FORCE_CTRL_CONFIG,),
                note="6 rows, row = axis: [opt, rigidity, rebound]"),
    CommandSpec(Cmd.SET_COMPLIANT_TYPE, request=(F.COMPLIANCE_TYPE, F.SENSOR_COMPENSATION)),
    CommandSpec(Cmd.GET_COMPLIANT_TYPE, reply=(F.SENSOR_COMPENSATION, F.COMPLIANCE_TYPE)),
    CommandSpec(Cmd.SET_TORQUE_SENSOR_COMM, request=(F.IP_ADDR, F.PORT, F.COMM_TYPE)),
    CommandSpec(Cmd.GET_TORQUE_SENSOR_COMM, reply=(F.COMM_TYPE, F.IP_ADDR, F.PORT),
                note="type 1: the SDK reads neither ip_addr nor port (nor errorCode)"),
    CommandSpec(Cmd.SET_TORQUE_SENSOR_FILTER, request=(F.SENSOR_FILTER,)),
    CommandSpec(Cmd.GET_TORQUE_SENSOR_FILTER, reply=(F.SENSOR_FILTER,)),
    CommandSpec(Cmd.SET_TORQUE_SENSOR_SOFT_LIMIT, request=(F.SENSOR_SOFT_LIMIT,),
                note="an object {Fx, Fy, Fz, Mx, My, Mz}"),
    CommandSpec(Cmd.GET_TORQUE_SENSOR_SOFT_LIMIT, reply=(F.SENSOR_SOFT_LIMIT,)),
    CommandSpec(Cmd.SET_VEL_COMPLIANT_CTRL, request=(F.COMPLIANT_CTRL,),
                note="[vc_level, rate1, rate2, rate3, rate4]"),
    CommandSpec(Cmd.SET_COMPLIANCE_CONDITION, request=(F.COMPLIANT_CONDITION,)),
    CommandSpec(Cmd.SET_FT_CTRL_FRAME, request=(F.FT_FRAME,)),
    CommandSpec(Cmd.GET_FT_CTRL_FRAME, reply=(F.FT_FRAME,)),
    CommandSpec(Cmd.GET_TORQUE_SENSOR_DATA, request=(F.COMM_TYPE,),
                reply=(F.SENSOR_DATA_STATUS, F.SENSOR_ERRCODE, F.SENSOR_DATA),
                note="type 1 actual, 2 general, 3 real"),
    CommandSpec(Cmd.GET_TOOL_DRIVE_STAT, reply=(F.ENABLE_FLAG, F.DRIVE_STAT),
                note='(sic) "stat"'),
    CommandSpec(Cmd.SET_TOOL_DRIVE_FRAME, request=(F.TOOL_DRAG_FRAME,)),
    CommandSpec(Cmd.GET_TOOL_DRIVE_FRAME, reply=(F.TOOL_DRAG_FRAME,)),
    CommandSpec(Cmd.SET_FUSION_DRIVE_SENSITIVITY_LEVEL, request=(F.SENSITIVITY_LEVEL_FUSION,)),
    CommandSpec(Cmd.GET_FUSION_DRIVE_SENSITIVITY_LEVEL, reply=(F.SENSITIVITY_LEVEL_FUSION,)),
    CommandSpec(Cmd.SET_MOTION_LIMIT_WARNING_RANGE, request=(F.RANGE_LEVEL,)),
    CommandSpec(Cmd.GET_MOTION_LIMIT_WARNING_RANGE, reply=(F.RANGE_LEVEL,)),
    CommandSpec(Cmd.SET_COMPLIANT_SPEED_LIMIT, request=(F.ANGULAR_SPEED_LIMIT, F.SPEED_LIMIT)),
    CommandSpec(Cmd.GET_COMPLIANT_SPEED_LIMIT, reply=(F.SPEED_LIMIT, F.ANGULAR_SPEED_LIMIT)),
    CommandSpec(Cmd.SET_TORQUE_REF_POINT, request=(F.REF_POINT,)),
    CommandSpec(Cmd.GET_TORQUE_REF_POINT, reply=(F.REF_POINT,)),
    CommandSpec(Cmd.SET_END_SENSOR_SENSITIVITY_THRESHOLD, request=(F.THRESHOLD_PERCENT,)),
    CommandSpec(Cmd.GET_END_SENSOR_SENSITIVITY_THRESHOLD, reply=(F.THRESHOLD_PERCENT,)),
    # trajectory recording: every reply's errorCode a string (an int aborts JAKA's SDK)
    CommandSpec(Cmd.SET_TRAJ_CONFIG, request=(F.TRAJ_ACC, F.RPY_INTERVAL, F.TRAJ_VEL,
                                             F.XYZ_INTERVAL),
                note="intervals with 2 decimals; values unconverted (mm, deg, mm/s, mm/s²)"),
    CommandSpec(Cmd.GET_TRAJ_CONFIG, reply=(F.XYZ_INTERVAL, F.RPY_INTERVAL, F.TRAJ_VEL,
                                           F.TRAJ_ACC)),
    CommandSpec(Cmd.SET_TRAJ_SAMPLE_MODE, request=(F.TRAJ_FILENAME, F.TRAJ_MODE)),
    CommandSpec(Cmd.GET_TRAJ_SAMPLE_STATUS, reply=(F.SAMPLE_STATUS,), note="an int"),
    CommandSpec(Cmd.GET_EXIST_TRAJ_FILE_NAME, reply=(F.TRAJ_FILE_NAMES,),
                note="at most 256 names, each cut to 255 characters"),
    CommandSpec(Cmd.RENAME_TRAJ_FILE_NAME, request=(F.TRAJ_DEST, F.TRAJ_SRC)),
    CommandSpec(Cmd.REMOVE_TRAJ_FILE, request=(F.TRAJ_FILE_NAME,)),
    CommandSpec(Cmd.GENERATE_TRAJ_EXE_FILE, request=(F.TRAJ_FILE_NAME,),
                note='the replay loads as program "track/<name>"'),
)
del F

#: cmdName → :class:`CommandSpec`, for every command this library can encode.
COMMANDS: Mapping[str, CommandSpec] = MappingProxyType({s.name: s for s in _SPECS})


#: The fieldbus slaves' arrays in the status packet: (key prefix, IO type); each prefix has
#: ``_din``, ``_dout`` (ints) and ``_ain``, ``_aout`` (doubles), as JAKA's SDK reads them.
FIELDBUS_SLAVES = (("mb_slave", IOType.MODBUS_SLAVE), ("pn_dev", IOType.PROFINET_SLAVE),
                   ("eip_adpt", IOType.EIP_SLAVE))
#: The four arrays of an IO group, in the order ``extio``'s ``status`` lists them.
IO_ARRAYS = ("din", "dout", "ain", "aout")


class StatusField:
    """Keys of a status packet (port 10000, port 10004 and the ``get_data`` reply) that this
    library reads; a real packet has more (docs/protocol.md, "Status packet")."""

    LEN = "len"
    JOINT_ACTUAL_POSITION = "joint_actual_position"   # [6] deg, measured
    JOINT_POSITION = "joint_position"                 # [6] deg, commanded
    ACTUAL_POSITION = "actual_position"               # [6] mm / deg RPY, measured TCP
    POSITION = "position"                             # [6] mm / deg RPY, commanded TCP
    TASK_STATE = "task_state"
    TASK_MODE = "task_mode"
    INTERP_STATE = "interp_state"
    POWERED_ON = "powered_on"
    ENABLED = "enabled"
    PAUSED = "paused"
    INPOS = "inpos"
    DRAG_STATUS = "drag_status"
    EMERGENCY_STOP = "emergency_stop"
    PROTECTIVE_STOP = "protective_stop"
    ON_SOFT_LIMIT = "on_soft_limit"
    ERRCODE = "errcode"                               # hex string, "0x0" = no error
    ERRMSG = "errmsg"
    RAPIDRATE = "rapidrate"                           # 1.0 = 100 %
    CURRENT_TOOL_ID = "current_tool_id"
    CURRENT_USER_ID = "current_user_id"
    DIN = "din"
    DOUT = "dout"
    AIN = "ain"
    AOUT = "aout"
    TIO_DIN = "tio_din"
    TIO_DOUT = "tio_dout"
    TIO_AIN = "tio_ain"
    TIO_RS_SIGNALS = "tio_rs_signals"                 # rows [name, chn, type, addr, value, Hz]
    MOTION_LINE = "motion_line"
    ERR_ADD_LINE = "err_add_line"
    EXECUTING_LINE = "executing_line"
    HOMED = "homed"                                   # 9 entries on a real controller
    INST_VEL = "instVel"                              # [6] joint speeds, top level
    MONITOR_DATA = "monitor_data"                     # an array: [scbMajor, scbMinor, cabinet
    # temperature, average power, average current, [6 joint rows of >= 10 numbers: [0] current,
    # [1] voltage, [2] temperature, [9] torque]]
    TORQSENSOR = "torqsensor"                         # [[commType, [ip, port], [mass, [x,y,z]]],
    # [status, errcode, [6] actual contact force, [6] raw reading, [6] real contact force]]
    RELAY_IO = "relay_io"
    EXTIO = "extio"                                   # {num, status: [[din],[dout],[ain],[aout]]}
    # the fieldbus slaves: <prefix>_din, _dout, _ain, _aout for each prefix of FIELDBUS_SLAVES
