#!/usr/bin/python3
"""A babbling device: 100 MB of random bytes on a pseudo-terminal that `rangekit FAMILY stream`
reads. Reports the stream's stderr size (bounded diagnostics, docs/reliability.md), its memory
(VmRSS at the start of the babble and the largest seen), and the bad-frame count of its
jsonl output against the count its summary lines and first lines report.

    /usr/bin/python3 bench/chaos/babble.py [--build build] [--megabytes 100] [--family uls|ls5|both]
"""

import argparse
import json
import os
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
import select
import termios
import threading
import tty

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def rss_kb(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def open_raw(path):
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
    tty.setraw(fd)
    attrs = termios.tcgetattr(fd)
    attrs[4] = attrs[5] = termios.B115200  # the emulators' factory speed: anything else is garbled
    termios.tcsetattr(fd, termios.TCSANOW, attrs)
    return fd


class Proxy:
    """The host's pty wired to the emulator until `babble` is set: the stream starts against a
    real device (its queries answered), then the device side goes quiet and random bytes take
    its place."""

    def __init__(self, master, device):
        self.master, self.device = master, device
        self.babble = threading.Event()
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        while not self.stop.is_set():
            ready, _, _ = select.select([self.master, self.device], [], [], 0.1)
            for fd in ready:
                try:
                    data = os.read(fd, 4096)
                except OSError:
                    return
                try:
                    if fd == self.master and not self.babble.is_set():
                        os.write(self.device, data)  # the host's commands reach the device
                    elif fd == self.device and not self.babble.is_set():
                        os.write(self.master, data)
                except OSError:
                    pass  # the device is gone once the babble starts


def wait_for_sample(path, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if os.path.exists(path):
            with open(path) as f:
                if '"kind"' in f.read():
                    return True
        time.sleep(0.05)  # polling a file the stream writes
    return False


def run_family(cli, family, megabytes, seed):
    with tempfile.TemporaryDirectory(prefix="chaos-babble-") as work:
        device_port = os.path.join(work, "device")
        emulator, _ = common.start_emulator(cli, family, device_port)
        device = open_raw(device_port)
        master, slave = os.openpty()
        tty.setraw(slave)
        link = os.path.join(work, "babble")
        os.symlink(os.ttyname(slave), link)
        out = os.path.join(work, "out.jsonl")
        err = os.path.join(work, "stderr.txt")
        proxy = Proxy(master, device)
        with open(err, "w") as err_file:
            stream = subprocess.Popen([cli, family, "stream", "--port", link, "--format", "jsonl", "--quiet",
                                       "--out", out, "--silence-ms", "600000"] if family == "ls5" else
                                      [cli, family, "stream", "--port", link, "--format", "jsonl", "--quiet",
                                       "--out", out], stdout=subprocess.DEVNULL, stderr=err_file)
            if not wait_for_sample(out, 30):
                stream.kill()
                raise RuntimeError(f"{family}: no sample before the babble")
            proxy.babble.set()
            common.stop(emulator)
            rng = random.Random(seed)
            total = megabytes * 1_000_000
            sent = 0
            start_rss = rss_kb(stream.pid)
            peak_rss = start_rss
            started = time.monotonic()
            while sent < total and stream.poll() is None:
                chunk = rng.randbytes(min(65536, total - sent))
                try:
                    sent += os.write(master, chunk)
                except OSError:
                    break
                peak_rss = max(peak_rss, rss_kb(stream.pid))
            elapsed = time.monotonic() - started
            alive = stream.poll() is None
            time.sleep(1.0)  # let the host take the last bytes the pty holds (measurement, not sync)
            stream.send_signal(signal.SIGINT)
            try:
                stream.wait(timeout=30)
            except subprocess.TimeoutExpired:
                stream.kill()
        proxy.stop.set()
        proxy.thread.join()
        os.close(master)
        os.close(slave)
        os.close(device)
        events = 0
        with open(out) as f:
            for line in f:
                item = json.loads(line)
                if item.get("event") == "bad_frame":
                    events += 1
        with open(err) as f:
            stderr_text = f.read()
        # "N more bad frames in the last 1 s" lines plus the lines printed in full.
        merged = sum(int(n) for n in re.findall(r"(\d+) more bad frames", stderr_text))
        full = len(re.findall(r"bad_frame: ", stderr_text))
        return {"sent": sent, "seconds": elapsed, "alive": alive, "stderr": len(stderr_text.encode()),
                "start_rss": start_rss, "peak_rss": peak_rss, "events": events, "merged": merged, "full": full}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--megabytes", type=int, default=100)
    parser.add_argument("--family", choices=["uls", "ls5", "both"], default="both")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    cli = common.cli_path(args.build)
    for family in (["uls", "ls5"] if args.family == "both" else [args.family]):
        r = run_family(cli, family, args.megabytes, args.seed)
        print(f"babble {family}: {r['sent'] / 1e6:.0f} MB in {r['seconds']:.0f} s, host alive {r['alive']}; "
              f"stderr {r['stderr']} bytes; VmRSS {r['start_rss']} kB at the start, at most {r['peak_rss']} kB; "
              f"{r['events']} bad_frame events in the jsonl, stderr lines in full {r['full']} + merged "
              f"{r['merged']} = {r['full'] + r['merged']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
