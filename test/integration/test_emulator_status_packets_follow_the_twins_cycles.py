"""The emulator's status packets go out right after the twin's cycle they show, not on a timer
of their own (emulator/status_pace.py): a client that times its commands by the packets'
arrival then times them by the twin's cycles.

The twin runs in sim time, paused, and the test steps it (real TCP on 127.0.0.1, the packets'
``timestamp`` = the stamp of the cycle shown, sim s: profile ``zu5s-1.5.14``). With a 0.4 s
period a packet is due every 50 cycles: stepped 50 cycles, the packet showing the 50th
arrives within 0.2 s of the step's end (wall clock, read to ~1 µs; it takes ~1 ms) — a timer
of 0.4 s started at the previous packet, stepped right after that packet, would send it
~0.39 s later. No packet shows a cycle in between. While no cycle ends (paused), the packets
go on every period on the wall clock, each showing the latest cycle.
"""
from __future__ import annotations

import dataclasses
import time

import pytest
from support.ros_harness import wait_until
from support.status_reader import StatusReader

from jaka_driver.common.models import load_model
from jaka_driver.emulator.handlers import CommandHandlers
from jaka_driver.emulator.profiles import profile_named
from jaka_driver.emulator.server import EmulatorServer
from jaka_driver.emulator.status_packet import status_fields
from jaka_driver.emulator.twin_controller import TwinController
from jaka_driver.sim import SimBackend

PERIOD = 0.4            # s between packets: 50 cycles of 8 ms
CYCLES = 50
PROMPT = 0.2            # s of wall time a packet may follow its cycle's step by: a loaded
                        # machine's wake-up, far under the ~0.39 s a timer of its own takes


@pytest.fixture(scope="module")
def stepped_emulator():
    """An emulator server on a paused sim-time zu5 twin, its status period 0.4 s, and a
    reader of its stream: (backend, server, reader)."""
    profile = profile_named("zu5s-1.5.14")
    model = dataclasses.replace(load_model("zu5"), io_sizes=profile.io_sizes)
    backend = SimBackend(model, sim_time=True, real_time_factor=0)
    backend.clock.pause()
    backend.start()
    controller = TwinController(backend, profile)
    server = EmulatorServer(CommandHandlers(controller), lambda: status_fields(controller),
                            command_port=0, status_port=0, period=PERIOD, data_port=0,
                            arm=backend)
    server.start()
    reader = StatusReader(server.status_port)
    reader.start()
    try:
        yield backend, server, reader
    finally:
        reader.close()
        server.stop()
        controller.close()
        backend.shutdown()


def _stamps(reader: StatusReader, since: float) -> list:
    """(receipt s, the cycle shown: the packet's timestamp, sim s) since ``since``."""
    return [(t, packet["timestamp"]) for t, packet in reader.after(since)]


def test_a_due_cycle_is_sent_at_once_and_no_cycle_between_is_sent(stepped_emulator):
    backend, server, reader = stepped_emulator
    assert wait_until(lambda: reader.packets, 2.0), "no status packet"
    for _ in range(3):
        n = len(reader.packets)
        assert wait_until(lambda: len(reader.packets) > n, 2.0)   # step right after a packet
        shown = reader.packets[-1][1]["timestamp"]
        assert backend.clock.step(CYCLES, 5.0)
        stepped = time.monotonic()
        assert wait_until(lambda: any(s > shown for _, s in _stamps(reader, stepped - 1)), 2.0)
        arrival, stamp = next((t, s) for t, s in _stamps(reader, stepped - 1) if s > shown)
        assert stamp == pytest.approx(shown + PERIOD, abs=1e-9)      # the 50th cycle, not one between
        assert arrival - stepped < PROMPT, (
            f"the due cycle's packet came {1e3 * (arrival - stepped):.1f} ms after its step")
    assert server.pacer.on_cycle >= 3


def test_a_paused_twin_still_gets_its_packets_on_the_wall_clock(stepped_emulator):
    backend, server, reader = stepped_emulator
    latest = backend.state().stamp
    t0 = time.monotonic()
    time.sleep(3 * PERIOD + 0.05)
    paused = _stamps(reader, t0)
    assert len(paused) >= 2, f"{len(paused)} packets in {3 * PERIOD:.1f} s paused"
    assert all(s == pytest.approx(latest, abs=1e-9) for _, s in paused)
    assert server.pacer.on_wall_clock >= 2
