"""The line ``python -m jaka_driver.emulator`` prints on stdout once its ports accept
connections, written by :mod:`.__main__` and read by :mod:`.process` (and by anyone who starts
the emulator and waits for it): ``jaka_emulator ready: model zu5, host 127.0.0.1, command port
P, status port Q, data port R; ...``.
"""
from __future__ import annotations

import re
from typing import Optional, Tuple

READY = "jaka_emulator ready:"
_PORTS = re.compile(r"command port (\d+), status port (\d+), data port (\d+)")


def ready_line(model: str, host: str, command_port: int, status_port: int, data_port: int,
               more: str) -> str:
    """The line, ``more`` (the profile, the start state...) after the ports."""
    return (f"{READY} model {model}, host {host}, command port {command_port}, status port "
            f"{status_port}, data port {data_port}; {more}")


def ports_of(line: str) -> Optional[Tuple[int, int, int]]:
    """(command, status, data) port of a ready line; None for any other line."""
    match = _PORTS.search(line) if line.startswith(READY) else None
    return None if match is None else (int(match[1]), int(match[2]), int(match[3]))
