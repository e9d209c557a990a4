"""The emulator as a subprocess, for tests that kill and restart "the controller".

``EmulatorProcess`` starts ``python -m jaka_driver.emulator`` with the current interpreter,
waits for its ready line, and owns the process: :meth:`kill` makes the controller vanish
(SIGKILL, no goodbye on any socket), :meth:`stop` ends it cleanly. Every process started here
is ended here (``with`` or :meth:`stop`).
"""
from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import tempfile
import threading
from pathlib import Path
from typing import Optional

from .ready_line import ports_of

_SRC = Path(__file__).resolve().parents[2]


class EmulatorProcess:
    """``model`` served on ``host``; port 0 lets the emulator pick (read the bound ports from
    :attr:`command_port` / :attr:`status_port` after :meth:`start`). stderr (the emulator's
    log) goes to ``log_path`` (a temporary file by default)."""

    def __init__(self, model: str = "zu5", host: str = "127.0.0.1", command_port: int = 0,
                 status_port: int = 0, log_path: Optional[str] = None, *extra_args: str,
                 data_port: int = 0, profile: Optional[str] = None,
                 period: Optional[float] = None, start: Optional[str] = None):
        """``profile``, ``period`` and ``start`` are the emulator's ``--profile``, ``--period``
        and ``--start`` (None: the emulator's defaults)."""
        options = {"--profile": profile, "--period": period, "--start": start}
        extra_args = tuple(extra_args) + tuple(
            arg for name, value in options.items() if value is not None
            for arg in (name, str(value)))
        self.model = model
        self.host = host
        self.command_port = command_port
        self.status_port = status_port
        self.data_port = data_port
        self.extra_args = extra_args
        self.log_path = log_path or os.path.join(tempfile.gettempdir(),
                                                 f"jaka_emulator_{os.getpid()}.log")
        self.proc: Optional[subprocess.Popen] = None
        self._reader: Optional[threading.Thread] = None

    def start(self, timeout: float = 30.0) -> "EmulatorProcess":
        env = os.environ.copy()
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(_SRC), env.get("PYTHONPATH")]))
        args = [sys.executable, "-m", "jaka_driver.emulator", "--model", self.model,
                "--host", self.host, "--command-port", str(self.command_port),
                "--status-port", str(self.status_port), "--data-port", str(self.data_port),
                *self.extra_args]
        with open(self.log_path, "ab") as log:
            self.proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=log, env=env,
                                         start_new_session=True)
        lines: queue.Queue = queue.Queue()
        self._reader = threading.Thread(target=self._read_stdout, args=(self.proc, lines),
                                        daemon=True, name="emulator-stdout")
        self._reader.start()
        try:
            while True:
                line = lines.get(timeout=timeout)
                if line is None:
                    raise RuntimeError(f"the emulator exited before it was ready; log:\n"
                                       f"{self.log()}")
                ports = ports_of(line)
                if ports is not None:
                    self.command_port, self.status_port, self.data_port = ports
                    return self
        except queue.Empty:
            self.stop()
            raise RuntimeError(f"the emulator was not ready within {timeout} s; log:\n"
                               f"{self.log()}") from None

    @staticmethod
    def _read_stdout(proc: subprocess.Popen, lines: queue.Queue) -> None:
        # The only reader and closer of the pipe: it ends at EOF, when the process is gone.
        with proc.stdout:
            for raw in proc.stdout:
                lines.put(raw.decode(errors="replace"))
        lines.put(None)

    def log(self) -> str:
        try:
            return Path(self.log_path).read_text(errors="replace")[-4000:]
        except OSError:
            return ""

    @property
    def alive(self) -> bool:
        return self.proc is not None and self.proc.poll() is None

    def kill(self) -> None:
        """SIGKILL: the controller disappears without closing anything itself (the kernel
        resets its connections)."""
        if self.alive:
            os.killpg(self.proc.pid, signal.SIGKILL)
        if self.proc is not None:
            self.proc.wait()

    def stop(self, timeout: float = 5.0) -> None:
        """SIGTERM (clean shutdown), then SIGKILL if needed. Idempotent."""
        if self.alive:
            os.killpg(self.proc.pid, signal.SIGTERM)
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                pass
        self.kill()
        if self._reader is not None:
            self._reader.join(2.0)

    def __enter__(self) -> "EmulatorProcess":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
