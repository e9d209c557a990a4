"""The garbage collector's pauses of a process, for :mod:`bench.node_profile` (bench only).

``node_profile`` puts this folder first on the node's ``PYTHONPATH`` and names a file in
``JAKA_PROBE_GC``; Python imports this module at start-up (``site``), which then times every
collection with ``gc.callbacks`` and writes the running totals to that file once a second
(one small thread). Without ``JAKA_PROBE_GC`` it does nothing. It shadows the system's own
``sitecustomize`` (Debian's only installs an apport hook), so it is never on the path of a
process that is not being profiled.
"""
import os

_PATH = os.environ.get("JAKA_PROBE_GC")
if _PATH:
    import gc
    import json
    import threading
    import time

    _totals = {"collections": [0, 0, 0], "pause_s": [0.0, 0.0, 0.0], "max_s": [0.0, 0.0, 0.0],
               "over_1ms": 0, "collected": 0}
    _started = threading.local()

    def _timed(phase, info):
        if phase == "start":
            _started.t = time.perf_counter()
            return
        t0 = getattr(_started, "t", None)
        if t0 is None:
            return
        pause = time.perf_counter() - t0
        g = info.get("generation", 0)
        _totals["collections"][g] += 1
        _totals["pause_s"][g] += pause
        _totals["max_s"][g] = max(_totals["max_s"][g], pause)
        _totals["over_1ms"] += pause > 1e-3
        _totals["collected"] += info.get("collected", 0)

    def _write():
        while True:
            time.sleep(1.0)
            tmp = f"{_PATH}.{os.getpid()}.tmp"
            with open(tmp, "w") as f:
                json.dump({"pid": os.getpid(), "time": time.monotonic(), **_totals}, f)
            os.replace(tmp, _PATH)

    gc.callbacks.append(_timed)
    threading.Thread(target=_write, name="gc-probe", daemon=True).start()
