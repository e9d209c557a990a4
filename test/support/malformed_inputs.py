"""What the malformed-input tests share: how deep "deep" is, and every status key
``parse_status`` reads (each must survive a value of the wrong type)."""

DEEP = 100_000   # levels of nesting that end Python's parser with RecursionError

STATUS_KEYS_READ = (
    "joint_actual_position", "joint_position", "actual_position", "instVel", "monitor_data",
    "powered_on", "enabled", "emergency_stop", "protective_stop", "on_soft_limit", "inpos",
    "paused", "drag_status", "task_state", "task_mode", "interp_state", "current_tool_id",
    "current_user_id", "errcode", "errmsg", "rapidrate", "din", "dout", "ain", "aout",
    "tio_din", "tio_dout", "tio_ain", "motion_line", "homed", "torqsensor")
