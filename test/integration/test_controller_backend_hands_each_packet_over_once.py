"""The controller backend keeps one latest status packet and hands each one over once: a reader
that follows its samples (``wait_for_sample`` / ``states_since``, as the node's publisher does)
gets every packet the link received, in order, none twice, against the scripted fake controller
(a packet every 8 ms). While the link is down no sample comes, and the wait says so."""
from __future__ import annotations

import time

from support.fake_controller import backend, fake  # noqa: F401 - fixtures


def _packets(backend) -> int:
    counts = backend.link.counters()
    return next(v for k, v in counts.items() if k.startswith("status port") and
                k.endswith(" packets"))


def _follow(backend, packets: int, timeout: float = 30.0) -> list[float]:
    """Stamps of the samples a follower gets while the link receives ``packets`` packets."""
    stamps = []
    last = backend.state().stamp
    until = _packets(backend) + packets
    end = time.monotonic() + timeout
    while _packets(backend) < until and time.monotonic() < end:
        if not backend.wait_for_sample(last, 0.2):
            continue
        for st in backend.states_since(last):
            stamps.append(st.stamp)
            last = st.stamp
    return stamps


def test_a_follower_gets_every_packet_once_in_order(backend):
    before = _packets(backend)
    stamps = _follow(backend, 150)       # 1.2 s of packets every 8 ms, however long they take
    received = _packets(backend) - before
    assert received >= 150, received
    assert all(b > a for a, b in zip(stamps, stamps[1:])), "a sample handed over twice"
    # Packets completed by one TCP read share their receipt time and count as one sample;
    # otherwise every packet is one sample (one either side of the window's edges).
    assert len(stamps) >= 0.9 * received - 2, (len(stamps), received)
    assert len(stamps) <= received + 2


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
