#!/usr/bin/python3
"""Unplug cycles: the emulator is killed (the pty vanishes, as when a USB adapter is pulled)
and started again on the same path while `rangekit FAMILY stream` runs. Per family it reports
how many cycles resumed, the time from the emulator's ready line to the first sample after
the reconnect (slowest and median), and what the cut left behind: bad frames, suspect
samples, and joined lines (a sample printed between the disconnect and the reconnect).

    /usr/bin/python3 bench/chaos/unplug.py [--build build] [--cycles 30] [--family uls|ls5|both]
"""

import argparse
import os
import signal
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def is_event(kind):
    return lambda item: item.get("event") == kind


def is_sample(item):
    return "kind" in item


def run_family(cli, family, cycles, hold_s):
    with tempfile.TemporaryDirectory(prefix="chaos-unplug-") as work:
        port = os.path.join(work, family)
        emulator, _ = common.start_emulator(cli, family, port)
        stream = common.LiveStream(cli, family, port)
        resumed, latencies, bad_frames, suspect, joined = 0, [], 0, 0, 0
        try:
            if stream.wait_for(is_sample, 30) is None:
                raise RuntimeError("no first sample")
            for _ in range(cycles):
                common.stop(emulator, signal.SIGKILL)  # pulled: no goodbye on the line
                if stream.wait_for(is_event("disconnected"), 30) is None:
                    print(f"  {family}: no disconnect reported")
                    break
                time.sleep(hold_s)  # unplugged for a moment (the scenario, not synchronisation)
                emulator, ready = common.start_emulator(cli, family, port)
                # Everything up to the first sample after the reconnect.
                reconnected = False
                while True:
                    entry = stream.wait_for(lambda item: True, 30)
                    if entry is None:
                        break
                    at, item = entry
                    if item.get("event") == "bad_frame":
                        bad_frames += 1
                    elif item.get("event") == "reconnected":
                        reconnected = True
                    elif is_sample(item):
                        if item.get("suspect"):
                            suspect += 1
                        if not reconnected:
                            joined += 1
                            continue
                        resumed += 1
                        latencies.append(at - ready)
                        break
        finally:
            common.stop(emulator)
            stream.close()
        return resumed, latencies, bad_frames, suspect, joined


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--cycles", type=int, default=30)
    parser.add_argument("--hold", type=float, default=0.2, help="seconds unplugged per cycle")
    parser.add_argument("--family", choices=["uls", "ls5", "both"], default="both")
    args = parser.parse_args()
    cli = common.cli_path(args.build)
    ok = True
    for family in (["uls", "ls5"] if args.family == "both" else [args.family]):
        resumed, latencies, bad, suspect, joined = run_family(cli, family, args.cycles, args.hold)
        slowest = f"{1000 * max(latencies):.0f} ms" if latencies else "-"
        median = f"{1000 * statistics.median(latencies):.0f} ms" if latencies else "-"
        print(f"unplug {family}: {resumed}/{args.cycles} cycles resumed; ready -> first sample: slowest {slowest}, "
              f"median {median}; bad frames {bad}, suspect samples {suspect}, samples before the reconnect {joined}")
        ok = ok and resumed == args.cycles
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
