"""``python -m jaka_driver.emulator --model zu5 [--profile fw-1.7.2] [--host 127.0.0.1]
[--command-port 10001] [--status-port 10000] [--data-port 10004] [--period S] [--start STATE]
[--dh-from MODEL] [--calibration FILE|SEED] [--scene FILE] [--programs DIR] [--force-sensor]
[--gripper none|dh_pgi|suction] [--realtime-priority N]`` — also ``rosrun jaka_driver jaka_emulator ...``; ``--help`` lists the controller profiles.

Prints one line (:mod:`.ready_line`: ``jaka_emulator ready: model zu5, host 127.0.0.1, command
port P, status port Q, data port R; ...``) on stdout once its ports accept connections (port 0
picks free ports; the line says which), then serves until SIGINT or SIGTERM.
"""
from __future__ import annotations

import argparse
import logging
import signal
import sys
import threading

from ..common.models import MODEL_NAMES, load_model
from ..common.tool_urdf import TOOLS
from ..host import heap, latency_hint, realtime
from .handlers import EMULATOR_COMMANDS
from .profiles import ALIASES, DEFAULT_PROFILE, PROFILES, START_STATES
from .ready_line import ready_line


def _parser() -> argparse.ArgumentParser:
    extra = "\n".join(f"  {name}: {what}" for name, what in EMULATOR_COMMANDS.items())
    profiles = "\n".join(f"  {p.name}: {p.summary}.\n    {p.describe()}"
                         for p in PROFILES.values())
    profiles += "".join(f"\n  {old}: the former name of {new}" for old, new in ALIASES.items())
    parser = argparse.ArgumentParser(
        prog="jaka_emulator", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="A JAKA controller emulated on the MuJoCo twin, over JAKA's TCP protocol.",
        epilog=f"controller profiles (--profile):\n{profiles}\n\n"
               f"emulator-only commands (JSON on the command port):\n{extra}")
    parser.add_argument("--model", default="zu5", choices=MODEL_NAMES, help="arm model")
    parser.add_argument("--profile", default=DEFAULT_PROFILE,
                        choices=[*PROFILES, *ALIASES],
                        help=f"controller generation (default {DEFAULT_PROFILE}; see below)")
    parser.add_argument("--start", default=None, choices=START_STATES,
                        help="start state: off (powered off, disabled), on (powered, disabled), "
                             "enabled; default the profile's")
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to bind (default 127.0.0.1; 0.0.0.0 for every interface)")
    parser.add_argument("--command-port", type=int, default=10001, help="0 = any free port")
    parser.add_argument("--status-port", type=int, default=10000, help="0 = any free port")
    parser.add_argument("--data-port", type=int, default=10004,
                        help="data_request port (zlib status replies); 0 = any free port")
    parser.add_argument("--period", type=float, default=None,
                        help="s between two status packets on the status port; default the "
                             "profile's")
    parser.add_argument("--dh-from", default=None, choices=MODEL_NAMES, metavar="MODEL",
                        help="the arm's chain is MODEL's (a controller whose arm is not "
                             "--model); the twin moves on it and get_dh_param answers it")
    parser.add_argument("--calibration", default=None, metavar="FILE|SEED",
                        help="a calibrated arm: an integer seed perturbs the chain by up to "
                             "0.4 mm and 0.005 deg per parameter; a file holds get_dh_param's "
                             "rows (alpha deg, a mm, d mm, joint_homeoff deg). The twin moves "
                             "on it and get_dh_param answers it")
    parser.add_argument("--programs", default=None, metavar="DIR",
                        help="the folder of the programs JAKA's program commands load and play "
                             "(the twin's format, NAME.jdp; a client loads NAME or NAME.jks); "
                             "default this package's config/programs")
    parser.add_argument("--scene", default=None, help="workcell obstacles file for the twin")
    parser.add_argument("--force-sensor", action="store_true",
                        help="the arm carries a flange force/torque sensor: the twin's, "
                             "answering JAKA's torque-sensor and force-control commands and "
                             "filling the status packet's torqsensor (default: no sensor, as "
                             "most arms ship)")
    parser.add_argument("--gripper", default="none", choices=TOOLS,
                        help="the tool on the twin's tool connector: dh_pgi a DH-Robotics "
                             "gripper on RS485 channel 1 (slave 1, driven by Modbus frames "
                             "sent with send_tio_rs_command), suction a cup on tool DO 0 with "
                             "its vacuum on tool DI 0 (default none)")
    parser.add_argument("--io-loopback", action="store_true",
                        help="wire each output to the input of the same index")
    parser.add_argument("--realtime-priority", type=_priority, default=realtime.DEFAULT_PRIORITY,
                        metavar="N", help="SCHED_FIFO priority of the emulator's twin and status "
                        "push once it serves, as a controller's cycle runs in real time (default "
                        f"{realtime.DEFAULT_PRIORITY}; 0: the default policy); without the "
                        "privilege it logs why and runs at the default policy")
    parser.add_argument("--log-level", default="INFO")
    return parser


def _priority(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    why = realtime.priority_error(value)
    if why is not None:
        raise argparse.ArgumentTypeError(why)
    return value


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    scheduling = latency_hint.request_short_slice()     # done already by the script
    logging.basicConfig(level=args.log_level.upper(),
                        format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    logging.getLogger("jaka_driver.emulator").info("scheduling: %s", scheduling)
    from .app import Emulator   # imports MuJoCo: after argument errors are reported
    from .calibration import arm_model
    done = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: done.set())
    try:
        model = arm_model(load_model(args.model), args.dh_from, args.calibration)
        emulator = Emulator(model, args.host, args.command_port, args.status_port,
                            data_port=args.data_port, profile=args.profile, period=args.period,
                            start=args.start, scene=args.scene, io_loopback=args.io_loopback,
                            programs=args.programs or "default",
                            force_sensor=args.force_sensor, gripper=args.gripper)
        kept, took = heap.settle()      # before its threads run (host/heap.py)
        logging.getLogger("jaka_driver.emulator").info(
            "%d objects of start-up kept out of full garbage collections (collected in %.0f "
            "ms)", kept, took * 1e3)
        emulator.start()
        logging.getLogger("jaka_driver.emulator").info(
            "scheduling: %s", realtime.request_realtime(args.realtime_priority))
    except ValueError as exc:
        print(f"jaka_emulator: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"jaka_emulator: cannot serve on {args.host}: {exc}", file=sys.stderr)
        return 1
    print(ready_line(args.model, emulator.host, emulator.command_port, emulator.status_port,
                     emulator.data_port, f"{_chain(args)}profile {emulator.profile.name}, "
                     f"{'a force/torque sensor, ' if args.force_sensor else ''}"
                     f"{'' if args.gripper == 'none' else f'gripper {args.gripper}, '}started "
                     f"{emulator.start_state}, a packet every {emulator.period * 1000:g} ms"),
          flush=True)
    try:
        while not done.wait(0.5):
            pass
    finally:
        emulator.stop()
    return 0


def _chain(args) -> str:
    """The ready line's words on a chain that is not the model's own."""
    if args.dh_from is None and args.calibration is None:
        return ""
    words = [f"{args.dh_from}'s chain" if args.dh_from else "its chain"]
    if args.calibration is not None:
        words.append(f"calibrated ({args.calibration})")
    return " ".join(words) + ", "


if __name__ == "__main__":
    sys.exit(main())
