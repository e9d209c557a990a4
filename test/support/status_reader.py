"""A reader of an emulator's status stream (port 10000) for the tests, as a plain client reads
it (sockets and ``json``, nothing of the emulator's code): each packet decoded, with the
``time.monotonic()`` of the read that completed it."""
from __future__ import annotations

import json
import socket
import threading
import time


class StatusReader(threading.Thread):
    """Reads the status stream on 127.0.0.1:``port`` until :meth:`close`; ``packets`` holds
    (receipt s, the packet's fields) in order."""

    def __init__(self, port: int):
        super().__init__(daemon=True)
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=0.05)
        self.packets: list = []
        self.stop = threading.Event()

    def run(self) -> None:
        decoder, text = json.JSONDecoder(), ""
        while not self.stop.is_set():
            chunk = self._chunk()
            if chunk is None:
                return
            if not chunk:
                continue
            now = time.monotonic()
            text += chunk.decode()
            while True:
                start = text.find('{"len":')
                if start < 0:
                    break
                try:
                    packet, end = decoder.raw_decode(text, start)
                except ValueError:
                    break                   # the rest of it comes with the next read
                self.packets.append((now, packet))
                text = text[end:]

    def _chunk(self):
        """The next bytes read (b"" when none came within the socket's timeout), None once the
        stream has ended."""
        try:
            return self.sock.recv(65536) or None
        except socket.timeout:
            return b""
        except OSError:
            return None

    def after(self, t: float) -> list:
        """(receipt s, fields) of the packets received later than ``t`` (monotonic s)."""
        return [p for p in list(self.packets) if p[0] > t]

    def gaps(self, since: float) -> list:
        """s between consecutive packets received since ``since``."""
        times = [t for t, _ in self.after(since)]
        return [b - a for a, b in zip(times, times[1:])]

    def close(self) -> None:
        self.stop.set()
        self.join(2.0)
        self.sock.close()
