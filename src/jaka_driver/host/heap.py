"""The garbage collector in a long-running node: what start-up built is never garbage.

Start-up imports rospy, genpy, numpy, MuJoCo and Pinocchio and builds the model, the messages,
the services and the twin: some hundred thousand objects that live as long as the process.
CPython's collector walks every tracked object of the oldest generation in a full collection,
which it runs whenever the survivors of the younger collections reach a quarter of the old
ones. In the node that took 15–50 ms with the interpreter lock held (bench.node_profile's
garbage-collector probe: two full collections in the streams benchmark, the longest 31 and
48 ms), and every thread waits for it meanwhile — the twin's physics, the state publisher, the
service threads: a servo target's tail, a state topic's inter-arrival, a service's round trip.

:func:`settle` collects and moves what survives to the permanent generation (``gc.freeze``),
which no collection walks: a full collection then looks only at what was made since. A node
settles twice: once its backend is built, before any of its threads run (the collection
itself holds the interpreter lock for tens of ms: the twin's physics must not wait for it),
and once it is ready (then only the objects made in between are walked: a few ms). Nothing leaks: a frozen object freed by its reference count is freed as
before; only a reference cycle among start-up's own objects would stay, and start-up builds
none to drop.
"""
from __future__ import annotations

import gc
import time


def settle() -> tuple[int, float]:
    """Collect, then keep what survived out of every later collection: (how many objects are
    kept out now, how long the collection took, s)."""
    t0 = time.perf_counter()
    gc.collect()
    took = time.perf_counter() - t0
    gc.freeze()
    return gc.get_freeze_count(), took
