"""What the topic inputs did: a topic cannot answer, so every refusal and every stop of a
streamed input is published on ``~command_status`` (``diagnostic_msgs/DiagnosticStatus``: the
input's topic as ``name``, WARN for a refusal or a slowdown, OK for a stop, the driver's message
naming the field, the value and the limit, as the services' answers do; ``values``: the
result code and the input's counts) and counted in ``/diagnostics``.

A stream's end is seen by a watcher thread per input on the wall clock: ``timeout`` s after
the last accepted message it reports the stop the driver's watchdog made (the joint stream's
arm holds its last target; a velocity jog ramps to rest).
"""
from __future__ import annotations

import threading
import time
from collections import Counter

import rospy
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue

from ..common.results import Result
from ..host import realtime


class CommandStatus:
    """The status topic and the counts of every input (thread-safe)."""

    def __init__(self):
        self._pub = rospy.Publisher("~command_status", DiagnosticStatus, queue_size=20)
        self._lock = threading.Lock()
        self._counts: Counter = Counter()

    def publish(self, topic: str, level: int, message: str, code: int) -> None:
        with self._lock:
            counts = {k[1]: n for k, n in self._counts.items() if k[0] == topic}
        values = [KeyValue("ret", str(code))] + [KeyValue(k, str(n))
                                                  for k, n in sorted(counts.items())]
        self._pub.publish(DiagnosticStatus(level=level, name=topic, message=message,
                                           hardware_id="jaka_driver", values=values))

    def count(self, topic: str, what: str) -> None:
        with self._lock:
            self._counts[(topic, what)] += 1

    def accepted(self, topic: str) -> None:
        self.count(topic, "accepted")

    def refused(self, topic: str, result: Result) -> None:
        """A message the driver refused: counted and published (WARN)."""
        self.count(topic, "refused")
        rospy.logwarn_throttle(1.0, f"{topic} refused ({result.code}): {result.message}")
        self.publish(topic, DiagnosticStatus.WARN, result.message, result.code)

    def stopped(self, topic: str, message: str) -> None:
        """A stream that ended (its watchdog stopped it): counted and published (OK)."""
        self.count(topic, "stops")
        self.publish(topic, DiagnosticStatus.OK, message, 1)

    def diagnostics(self) -> dict:
        """``/diagnostics`` values: "<topic> <what>" → count."""
        with self._lock:
            return {f"{topic} {what}": str(n) for (topic, what), n in sorted(self._counts.items())}


class StreamEnd:
    """Reports a stream's stop ``timeout`` s (wall) after its last accepted message, once per
    stream: ``fed()`` on each accepted message. A message costs a clock read; only the first
    of a stream wakes the watcher, which then sleeps a timeout at a time (no thread wake-up
    per message: at 125 Hz those cost more CPU than the driver's call)."""

    def __init__(self, status: CommandStatus, topic: str, timeout: float, message: str):
        self._status, self._topic, self._timeout, self._message = status, topic, timeout, message
        self._started = threading.Event()
        self._last = 0.0
        threading.Thread(target=self._run, name=f"stream-end{topic}", daemon=True).start()

    def fed(self) -> None:
        self._last = time.monotonic()
        if not self._started.is_set():
            self._started.set()

    @realtime.runs_periodically
    def _run(self) -> None:
        while not rospy.is_shutdown():
            if not self._started.wait(1.0):
                continue
            while True:                     # a stream runs: until a timeout without a message
                remaining = self._last + self._timeout - time.monotonic()
                if remaining <= 0:
                    self._started.clear()
                    # a message between the check and the clear started a new stream
                    if time.monotonic() - self._last < self._timeout:
                        self._started.set()
                        continue
                    self._status.stopped(self._topic, self._message)
                    break
                time.sleep(remaining)
