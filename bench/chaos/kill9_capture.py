#!/usr/bin/python3
"""kill -9 during capture: `rangekit FAMILY stream --capture FILE` prints jsonl and writes the
SQLite capture; after a random 1-3 s it is killed with SIGKILL. The capture must then open
(`rangekit replay`), pass SQLite's integrity check, and hold every sample the stream had
printed before the last capture batch (the printed ones it lacks are counted as missing;
samples are matched by time and value).

    /usr/bin/python3 bench/chaos/kill9_capture.py [--build build] [--runs 30] [--family uls|ls5|both]
"""

import argparse
import json
import os
import random
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def key(item):
    return (item["time"], item.get("distance_m"), item.get("code"), item.get("kind"))


def run_once(cli, family, work, port, rng):
    capture = os.path.join(work, f"run-{rng.random():.9f}.sqlite")
    printed_path = capture + ".jsonl"
    with open(printed_path, "w") as printed_file:
        stream = subprocess.Popen([cli, family, "stream", "--port", port, "--format", "jsonl", "--quiet",
                                   "--capture", capture], stdout=printed_file, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(1.0, 3.0))  # the moment of the kill is the experiment
        stream.send_signal(signal.SIGKILL)
        stream.wait()
    with open(printed_path) as f:
        printed = [json.loads(line) for line in f if line.strip()]
        printed = [item for item in printed if "kind" in item]
    integrity = sqlite3.connect(capture).execute("PRAGMA integrity_check").fetchone()[0]
    replay = subprocess.run([cli, "replay", "--full-speed", "--format", "jsonl", capture],
                            capture_output=True, text=True)
    if replay.returncode != 0:
        return False, integrity, len(printed), 0, len(printed)
    replayed = [json.loads(line) for line in replay.stdout.splitlines() if line.strip()]
    replayed_keys = {key(item) for item in replayed if "kind" in item}
    missing = sum(1 for item in printed if key(item) not in replayed_keys)
    return True, integrity, len(printed), len(replayed_keys), missing


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--runs", type=int, default=30)
    parser.add_argument("--family", choices=["uls", "ls5", "both"], default="both")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    cli = common.cli_path(args.build)
    rng = random.Random(args.seed)
    ok = True
    for family in (["uls", "ls5"] if args.family == "both" else [args.family]):
        with tempfile.TemporaryDirectory(prefix="chaos-kill9-") as work:
            port = os.path.join(work, family)
            emulator, _ = common.start_emulator(cli, family, port)
            opened = intact = printed_total = captured_total = missing_total = worst_missing = 0
            try:
                for _ in range(args.runs):
                    replayed, integrity, printed, captured, missing = run_once(cli, family, work, port, rng)
                    opened += 1 if replayed else 0
                    intact += 1 if integrity == "ok" else 0
                    printed_total += printed
                    captured_total += captured
                    missing_total += missing
                    worst_missing = max(worst_missing, missing)
            finally:
                common.stop(emulator)
        print(f"kill -9 {family}: {opened}/{args.runs} captures replayed, {intact}/{args.runs} pass integrity_check; "
              f"{printed_total} samples printed, {captured_total} captured, {missing_total} printed but not "
              f"captured (worst run {worst_missing})")
        ok = ok and opened == args.runs and intact == args.runs
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
