"""What one status packet costs the controller path's reader thread, and a command reply the
service thread: µs of wall time and µs of the thread's CPU per packet, for this checkout and,
with ``--against``, another one in the same run.

``python -m bench.packet_parse [--against PATH] [--packets 3000] [--rounds 3]``

The packet is the evidence's default-profile packet (``test/data/status_packet.json``: 57 keys,
6.5 kB as the controller writes it), its joints changing from packet to packet as on a moving
arm (the IO arrays unchanged, as they are). Per packet:

* ``framing (every key decoded)`` — a default
  :class:`~jaka_driver.protocol.StatusStreamDecoder`'s ``.feed`` of the packet in one read,
  and ``parse_status of those`` — its dict → :class:`~jaka_driver.protocol.StatusPacket`;
* ``receiver: framing + parse_status`` — the reader thread's work: the decoder a
  :class:`~jaka_driver.protocol.StatusReceiver` builds (which may decode only what
  ``parse_status`` reads), then ``parse_status``; in one read (the usual case on 127.0.0.1),
  and in the 1448-byte TCP segments a real network delivers it in;
* ``reply`` — a ``servo_j`` reply read by the command client's decoder and ``parse_reply``.

The CPU time is the interpreter lock's time: the JSON parsers (``json``'s C scanner, msgspec)
and the field readers never release it, so a thread parsing a packet holds the lock for all of
its CPU time, and every other thread of the node (the servo_j service among them) waits.

Each checkout runs in a process of its own (its ``src`` first on ``sys.path``), the rounds
alternating between them, so that both share the machine's minute; the table gives each
measure's median over the rounds. Not part of ``make bench``: it explains a row, it is not one.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SEGMENT = 1448    # bytes of TCP payload per Ethernet frame

# Runs inside the measured checkout's process: prints one JSON line of {measure: [wall, cpu]}.
_MEASURE = r"""
import json, sys, time
from jaka_driver.protocol import StatusReceiver, StatusStreamDecoder, encode_status, parse_status
from jaka_driver.protocol.wire import HeadDecoder
from jaka_driver.protocol.replies import parse_reply
fields = json.loads(open(sys.argv[1]).read())
n, segment = int(sys.argv[2]), int(sys.argv[3])
q0 = list(fields["joint_actual_position"])
packets = []
for i in range(64):
    fields["joint_actual_position"] = [q + 0.001 * i for q in q0]
    fields["joint_position"] = [q + 0.001 * i for q in q0]
    packets.append(encode_status(fields))
reply = b'{"errorCode": "0", "errorMsg": "", "cmdName": "servo_j"}'

def per(fn, items):
    for item in items[:8]:
        fn(item)
    w0, c0 = time.perf_counter(), time.thread_time()
    for k in range(n):
        fn(items[k % len(items)])
    return [(time.perf_counter() - w0) / n * 1e6, (time.thread_time() - c0) / n * 1e6]

decoder = StatusStreamDecoder()
out = {"packet bytes": [len(packets[0]), 0]}
out["framing (every key decoded)"] = per(decoder.feed, packets)
decoded = [StatusStreamDecoder().feed(p)[0] for p in packets]
out["parse_status of those"] = per(parse_status, decoded)
# the reader thread's work: its receiver's own decoder, then parse_status
receiver = StatusReceiver("127.0.0.1").decoder
out["receiver: framing + parse_status"] = per(
    lambda p: [parse_status(f) for f in receiver.feed(p)], packets)
pieces = [[p[i:i + segment] for i in range(0, len(p), segment)] for p in packets]
out[f"receiver, the packet in {len(pieces[0])} reads"] = per(
    lambda ps: [parse_status(f) for s in ps for f in receiver.feed(s)], pieces)
head = HeadDecoder()
out["reply"] = per(lambda r: parse_reply(head.decode(r).value), [reply])
assert decoder.packets_dropped == 0 and receiver.packets_dropped == 0
print(json.dumps(out))
"""


def measure(checkout: Path, packets: int) -> dict:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(checkout / "src"), os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run([sys.executable, "-c", _MEASURE,
                           str(ROOT / "test" / "data" / "status_packet.json"), str(packets),
                           str(SEGMENT)], env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.packet_parse",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--against", help="another checkout (its root), measured in turn")
    parser.add_argument("--packets", type=int, default=3000)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    checkouts = [ROOT] + ([Path(args.against).resolve()] if args.against else [])
    runs: dict[Path, list[dict]] = {c: [] for c in checkouts}
    for r in range(args.rounds):
        for checkout in checkouts if r % 2 == 0 else checkouts[::-1]:
            runs[checkout].append(measure(checkout, args.packets))
    print(f"per packet, median of {args.rounds} rounds of {args.packets}; "
          f"load {os.getloadavg()[0]:.2f}")
    names = list(runs[ROOT][0])
    header = "".join(f" | {c.name} µs wall | µs CPU (lock held)" for c in checkouts)
    print(f"| measure{header} |")
    print("|---" * (1 + 2 * len(checkouts)) + "|")
    for name in names:
        cells = ""
        for c in checkouts:
            wall = statistics.median(m[name][0] for m in runs[c])
            cpu = statistics.median(m[name][1] for m in runs[c])
            cells += f" | {wall:.1f} | {cpu:.1f}" if name != "packet bytes" else \
                f" | {wall:.0f} B | —"
        print(f"| {name}{cells} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
