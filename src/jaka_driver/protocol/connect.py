"""Opening a TCP connection to a controller's port: the one way the command client and the
status readers connect, and the size they read in."""
from __future__ import annotations

import socket

from .errors import ConnectFailed

#: bytes asked of the socket per read
RECV_SIZE = 65536


def open_connection(host: str, port: int, timeout: float, what: str) -> socket.socket:
    """A connection to ``host``:``port`` within ``timeout`` s, without Nagle's delay; ``what``
    names it in the error. Raises :class:`ConnectFailed` with what to check."""
    try:
        sock = socket.create_connection((host, port), timeout=timeout)
    except OSError as exc:
        raise ConnectFailed(
            f"cannot open the {what} connection to {host}:{port} ({exc}); check the controller's "
            f"IP address, that it is switched on, and that port {port} is reachable from this "
            "machine") from None
    # Commands are small and latency-bound (servo set-points every 8 ms): no Nagle delay.
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock
