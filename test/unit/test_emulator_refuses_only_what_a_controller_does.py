"""Every value check the emulator applies to a request, each with where a controller is shown
refusing it (docs/protocol.md restates the evidence; "SDK" = JAKA's SDK 2.1.14 header or its
probe on the wire, "clients" = public clients' recorded sessions) or what the arm itself has (its
model's limits, its frames, its IO). The emulator stands in for a controller: it refuses only
what the evidence shows a controller refusing, and adds no range of its own (docs/design.md,
"Where a new capability lives", 4). A new check without a source here fails this test; so does
a check listed here that the emulator no longer applies.

Found by reading the emulator's source: every call of the field readers with a bound
(``integer``'s range, ``number``'s ``lo``/``hi``/``positive``), and every call of a shared
value check (the force settings' ranges, the servo filters' spec, the joint limits)."""
import ast
from pathlib import Path

import jaka_driver.emulator as emulator

EMULATOR = Path(emulator.__file__).parent
READERS = {"integer", "number"}
#: the shared value checks the emulator calls, by name
CHECKS = {"_checked", "checked_spec", "check_limits"}

ENUM = "SDK header: the field's enumeration (docs/protocol.md)"
FLAG = "SDK: a 0/1 flag (docs/protocol.md)"
ARM_JOINTS = "the arm: its joint limits (the model's, docs/models.md), as a controller's"
ARM_PAYLOAD = "the arm: its rated payload (the model's max_payload_kg)"
NOT_ON_RECORD = "a JSON int of the SDK's width: the range is not on record (sensor_commands)"
SENSOR_RANGE = ("the sensor: its measuring range (force_sensor.range of the arm's model), and "
                "the SDK header's orders of the force settings (docs/protocol.md, 'Torque sensor')")
#: not on record: the driver's ceiling of a rebound, shared through backend/force_checks.py
REBOUND = SENSOR_RANGE + "; the rebound's ceiling (20 N/mm, 200 N·m/rad) is the driver's"

#: (module, reader or check, the field as the source names it) → the source
SOURCES = {
    ("arm_commands", "integer", "Field.REL_FLAG"): "SDK §6: relFlag INCR 1 / ABS 0",
    ("arm_commands", "number", "Field.CIRCLE_CNT"): "SDK: circle_cnt a count of turns, >= 0",
    ("arm_commands", "integer", "Field.CIRCLE_MODE"): "SDK: circle_mode an int 0–3 (protocol.md)",
    ("arm_commands", "number", "Field.TOL"): "SDK: the blending tolerance, a length >= 0",
    ("arm_commands", "integer", "Field.JOG_MODE"): "clients: jog_mode 0–3 (protocol.md)",
    ("arm_commands", "integer", "Field.JNUM"): "clients: jnum, the axis 0–5 (protocol.md)",
    ("arm_commands", "integer", "Field.STEP_NUM"):
        "SDK §6: stepNum an unsigned int, 0 refused; no upper bound (1000 sent)",
    ("arm_commands", "number", "Field.SPEED"): "recorded: a move at speed 0 is refused (clients)",
    ("arm_commands", "number", "Field.ACCEL"): "recorded: a move at accel 0 is refused (clients)",
    ("arm_commands", "integer", "Field.COORD_MAP"): "clients: coord_map 0–2 (protocol.md)",
    ("force_commands", "number", "Field.MASS"): ARM_PAYLOAD,
    ("force_commands", "integer", "'type'"): "SDK §5: get_torque_sensor_data type 1–3",
    ("force_commands", "integer", "'axis'"): "SDK §5: axis 0..5",
    ("force_commands", "integer", "'opt'"): FLAG,
    ("force_commands", "integer", "'ftNnormalTrack'"): FLAG,
    ("force_commands", "integer", "'sensor_compensation'"): FLAG,
    ("force_commands", "integer", "'compliance_type'"): "SDK §5: compliance_type 0–2",
    ("force_commands", "integer", "'enable_flag'"): "SDK §5: enable_flag 1|0",
    ("force_commands", "integer", "'sensor_mode'"): "SDK §5: sensor_mode 1 on, 0 off",
    ("force_commands", "integer", "'ftFrame'"): "SDK §5: ftFrame 0 tool, 1 world",
    ("force_commands", "integer", "'toolDragFrame'"): "SDK §5: toolDragFrame 0 tool, 1 world",
    ("force_commands", "_checked", "admittance"): REBOUND,
    ("force_commands", "_checked", "tool_drive"): REBOUND,
    ("force_commands", "_checked", "velocity_compliance"):
        "SDK header: vc_level 1–3 and 1 > rate1 > … > 0 (docs/interface.md, 'Force')",
    ("force_commands", "_checked", "wrench_limits"): SENSOR_RANGE,
    # not on record: the twin's sensor filter at its 8 ms cycle (backend.force_checks)
    ("force_commands", "_checked", "filter_hz"):
        "the twin: a sensor filter cut-off 0–100 Hz (its force control's 8 ms cycle)",
    ("force_commands", "check_limits", "q"): ARM_JOINTS,
    ("io_commands", "integer", "Field.IO_TYPE"): "SDK: IO types 0–6 (protocol.md, 'IO')",
    ("io_commands", "integer", "Field.INDEX"): "the arm: its IO count (checked again per type)",
    ("program_commands", "integer", "Field.ID_NEW"):
        "clients: user variables by id 1–100 (protocol.md, 'Programs')",
    ("program_steps", "check_limits", "q"): ARM_JOINTS,
    ("sensor_commands", "integer", "key"): FLAG,
    ("sensor_commands", "number", "Field.MASS"): ARM_PAYLOAD,
    ("sensor_commands", "integer", "'type'"): NOT_ON_RECORD,
    ("sensor_commands", "integer", "'port'"): "a TCP port, 0–65535",
    ("sensor_commands", "integer", "'axis'"): "SDK §5: axis 0..5",
    ("sensor_commands", "integer", "'sensor_compensation'"): NOT_ON_RECORD,
    ("sensor_commands", "integer", "'compliance_type'"): NOT_ON_RECORD,
    ("sensor_commands", "number", "key"): "a soft limit: a magnitude, >= 0",
    ("sensor_commands", "integer", "'opt'"): NOT_ON_RECORD,
    ("sensor_commands", "integer", "'ftNnormalTrack'"): NOT_ON_RECORD,
    ("sensor_commands", "integer", "'sensor_brand'"): NOT_ON_RECORD,
    ("sensor_commands", "number", "'torqueSensorFilter'"): "a cut-off in Hz, >= 0 (0 = off)",
    ("sensor_commands", "integer", "'ftFrame'"): "SDK §5: ftFrame 0 tool, 1 world",
    ("sensor_commands", "integer", "'toolDragFrame'"): "SDK §5: toolDragFrame 0 tool, 1 world",
    ("sensor_commands", "integer", "'sensitivity_level'"): NOT_ON_RECORD,
    ("sensor_commands", "integer", "'range_level'"): NOT_ON_RECORD,
    ("sensor_commands", "number", "'speed_limit'"): "a speed limit, >= 0 (SDK: unconverted)",
    ("sensor_commands", "number", "'angular_speed_limit'"):
        "a speed limit, >= 0 (SDK: unconverted)",
    ("sensor_commands", "integer", "'ref_point'"): NOT_ON_RECORD,
    ("setting_commands", "integer", "key"):
        "SDK §2: frames by id 0–10 (the tables of 11 rows); SDK §6: mmf_max_buf an int >= 1",
    ("setting_commands", "integer", "Field.ID"): "SDK §2: a settable frame id 1–10",
    ("setting_commands", "number", "Field.MASS"): ARM_PAYLOAD,
    ("setting_commands", "number", "Field.RATE_VALUE"): "SDK §3: the speed ratio (0, 1]",
    ("setting_commands", "integer", "Field.FILTER_TYPE"): "SDK §6: filter_type 0–5",
    ("setting_commands", "number", "key"):
        "SDK §6: the filters' limits in the header's units, > 0 (a cut-off, a speed limit)",
    ("setting_commands", "checked_spec", "filter_type"):
        "the twin: above its range clamped, not refused (docs/twin.md, 'Servo filters'); "
        "refused only: a mean filter's weights all 0",
    ("setting_commands", "integer", "Field.SENSITIVITY_VAL"):
        "clients: set_clsn_sensitivity sensitivityVal 0–5 (protocol.md)",
    ("mounting_commands", "number", "Field.ANGLE_X"): "SDK header: set_installation_angle 0–180°",
    ("mounting_commands", "number", "Field.ANGLE_Z"): "SDK header: set_installation_angle 0–360°",
    ("network_watch", "integer", "Field.MOT_TYPE"):
        "SDK §11: motType MOT_KEEP 0 / MOT_PAUSE 1 / MOT_ABORT 2",
    ("network_watch", "number", "Field.TIME_LIMIT"): "SDK §11: timeLimit, a time in ms, >= 0",
    ("recording_commands", "integer", "Field.TRAJ_MODE"):
        "SDK §11: set_traj_sample_mode mode 1 on / 0 off",
    ("tool_io_commands", "_checked", "check_channel"):
        "SDK header §10: chn_id 0 = RS485H, 1 = RS485L",
    ("tool_io_commands", "_checked", "check_pin_mode"):
        "SDK header §10: pin_type 0 DI, 1 DO, 2 AI",
    ("tool_io_commands", "integer", "key"): "SDK §10: a C int of the request (its width)",
    ("arm_moves", "check_limits", "q"): ARM_JOINTS,
    ("arm_moves", "check_limits", "target()"): ARM_JOINTS,
    ("servo_mode", "check_limits", "q"): ARM_JOINTS,
}


def _name(func) -> str:
    return func.id if isinstance(func, ast.Name) else getattr(func, "attr", "")


def _field(call: ast.Call, name: str) -> str:
    """What a check is of: the reader's field, the force check's name, the filter's type."""
    if name in READERS:
        return ast.unparse(call.args[1])
    if name == "_checked":
        return _name(call.args[1])
    return ast.unparse(call.args[1] if name == "checked_spec" else call.args[0])


def checks_applied():
    found = set()
    for path in sorted(EMULATOR.glob("**/*.py")):
        if path.name == "wire_fields.py":          # the readers themselves
            continue
        module = path.stem
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Call):
                continue
            name = _name(node.func)
            if name in READERS:
                bounded = len(node.args) > 2 or any(
                    k.arg in ("lo", "hi", "positive") for k in node.keywords)
                if bounded:
                    found.add((module, name, _field(node, name)))
            elif name in CHECKS and node.args:
                found.add((module, name, _field(node, name)))
    return found


def test_every_value_check_of_the_emulator_has_a_source():
    found = checks_applied()
    assert len(found) > 40                        # the scan reads the handlers at all
    unsourced = sorted(found - set(SOURCES))
    assert not unsourced, f"value checks without a source: {unsourced}"
    gone = sorted(set(SOURCES) - found)
    assert not gone, f"listed here, no longer applied: {gone}"
    assert all(source.strip() for source in SOURCES.values())


def test_the_checks_the_evidence_removed_are_gone():
    """A low-pass cut-off above 62.5 Hz (servo_move_use_joint_LPF(125.0)), stepNum above 1000
    and reading type 0 were the emulator's own; JAKA's SDK sends all three."""
    text = (EMULATOR / "arm_commands.py").read_text()
    assert "Field.STEP_NUM, 1, 1000" not in text
    assert "clamp=True" in (EMULATOR / "setting_commands.py").read_text()
