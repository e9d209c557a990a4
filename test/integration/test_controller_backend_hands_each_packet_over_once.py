"""The controller backend hands each sample over once: a reader that follows its samples
(``wait_for_sample`` / ``states_since``, as the node's publisher does) gets every sample the
status thread made, in order, none twice — also a reader that falls behind by several packets
(the backend keeps the last ``HISTORY``), against the scripted fake controller (a packet every
8 ms). While the link is down no sample comes, and the wait says so."""
from __future__ import annotations

import time

import pytest

from support.fake_controller import backend, fake  # noqa: F401 - fixtures


def _packets(backend) -> int:
    counts = backend.link.counters()
    return next(v for k, v in counts.items() if k.startswith("status port") and
                k.endswith(" packets"))


def _follow(backend, packets: int, lag: float = 0.0, timeout: float = 30.0) -> list[float]:
    """Stamps of the samples a follower gets while the link receives ``packets`` packets; it
    sleeps ``lag`` s before each read."""
    stamps = []
    last = backend.state().stamp
    until = _packets(backend) + packets
    end = time.monotonic() + timeout
    while _packets(backend) < until and time.monotonic() < end:
        if not backend.wait_for_sample(last, 0.2):
            continue
        time.sleep(lag)
        for st in backend.states_since(last):
            stamps.append(st.stamp)
            last = st.stamp
    return stamps


def _made(backend) -> list[float]:
    """The receipt times of the samples the status thread makes from now on (a packet, or the
    packets one TCP read completed: one sample, the last), as it makes them."""
    made: list[float] = []
    store = backend.view.store

    def recorded(status, received):
        if not made or made[-1] != received:
            made.append(received)
        store(status, received)
    backend.view.store = recorded
    return made


@pytest.mark.parametrize("lag", [0.0, 0.1])
def test_a_follower_gets_every_sample_once_in_order(backend, lag):
    """``lag`` 0.1 s: the follower reads about once every 12 packets, and catches up."""
    made = _made(backend)
    try:
        stamps = _follow(backend, 150, lag)    # 1.2 s of packets every 8 ms, however long
    finally:
        del backend.view.store
    assert all(b > a for a, b in zip(stamps, stamps[1:])), "a sample handed over twice"
    assert len(stamps) >= 100, len(stamps)
    # every sample made from the follower's first to its last, none left out
    inside = [t for t in made if stamps[0] <= t <= stamps[-1]]
    assert stamps == inside, (len(stamps), len(inside))


def test_no_sample_while_the_link_is_down(fake, backend):
    fake.close()                      # the controller vanishes
    deadline = time.monotonic() + 5
    while backend.link.connected and time.monotonic() < deadline:
        time.sleep(0.02)
    assert not backend.link.connected
    last = backend.state().stamp
    assert not backend.wait_for_sample(time.time(), 0.3)
    st = backend.state()
    assert not st.connected and st.stamp > last   # the state says so, stamped when read
