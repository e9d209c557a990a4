"""A bare JSON-over-TCP client for the emulator's tests, as a third-party JAKA client would be:
plain sockets and ``json``, nothing of the emulator's code. Send an object (or any bytes), read
the next object; objects follow each other with no delimiter."""
from __future__ import annotations

import json
import socket
import time


class RawClient:
    def __init__(self, port: int, host: str = "127.0.0.1", timeout: float = 3.0):
        self.sock = socket.create_connection((host, port), timeout=timeout)
        self.timeout = timeout
        self.buf = b""
        self.decoder = json.JSONDecoder()

    def send(self, data: bytes) -> None:
        self.sock.sendall(data)

    def read_text(self, timeout: float = 0.0) -> str:
        """The next object's exact text; ``socket.timeout`` if none comes within ``timeout`` s
        (default: the connection's)."""
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            text = self.buf.lstrip().decode("utf-8", "replace")
            if text:
                try:
                    _, end = self.decoder.raw_decode(text)
                    used = len(text[:end].encode())
                    head, self.buf = self.buf.lstrip()[:used], self.buf.lstrip()[used:]
                    return head.decode()
                except ValueError:
                    pass
            self.sock.settimeout(max(0.01, deadline - time.monotonic()))
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("closed by the emulator")
            self.buf += chunk

    def read(self, timeout: float = 0.0) -> dict:
        return json.loads(self.read_text(timeout))

    def call(self, command: str, **fields) -> dict:
        self.send(json.dumps({"cmdName": command, **fields}).encode())
        return self.read()

    def closed_by_peer(self, timeout: float = 2.0) -> bool:
        self.sock.settimeout(timeout)
        try:
            return self.sock.recv(1) == b""
        except OSError:
            return True

    def close(self) -> None:
        self.sock.close()

    def __enter__(self) -> "RawClient":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def call_once(port: int, command: str, **fields) -> dict:
    """One request on a fresh connection."""
    with RawClient(port) as client:
        return client.call(command, **fields)
