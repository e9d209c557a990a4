"""The machine the driver runs on.

* :mod:`.latency_hint` — the threads' short time slice, asked for before any thread starts;
* :mod:`.realtime` — real-time priority for the threads once the process is ready, where the
  system allows it;
* :mod:`.native_library` — where the compiled libraries (IK, the twin's cycle) are;
* :mod:`.heap` — start-up's objects kept out of the garbage collector's full collections.

Imports nothing itself, so that ``from jaka_driver.host import latency_hint`` loads no more than
that module.
"""

__all__ = ["heap", "latency_hint", "native_library", "realtime"]
