"""Shared pieces of the chaos scripts: the CLI path, emulators, a stream read live."""

import json
import os
import queue
import signal
import subprocess
import threading
import time


def cli_path(build):
    path = os.path.abspath(os.path.join(build, "rangekit"))
    if not os.access(path, os.X_OK):
        raise SystemExit(f"{path}: not built (cmake --build {build} --target rangekit)")
    return path


def start_emulator(cli, family, port, extra=()):
    """Starts `rangekit sim FAMILY` with its measurement port at PORT; returns (process, ready time)."""
    if family == "uls":
        # Factory MO 0: the measurements leave on the configuration port.
        args = [cli, "sim", "uls", "--config-port", port, "--port", port + "-universal"]
    else:
        args = [cli, "sim", "ls5", "--port", port]
    proc = subprocess.Popen(args + list(extra), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            start_new_session=True)
    line = proc.stdout.readline()
    if "ready" not in line:
        proc.kill()
        raise RuntimeError(f"{family} emulator did not start: {line!r}")
    return proc, time.monotonic()


def stop(proc, sig=signal.SIGTERM):
    if proc.poll() is None:
        proc.send_signal(sig)
    try:
        proc.wait(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


class LiveStream:
    """`rangekit FAMILY stream --format jsonl` with its lines handed over as they come."""

    def __init__(self, cli, family, port, extra=()):
        self.proc = subprocess.Popen([cli, family, "stream", "--port", port, "--format", "jsonl", "--quiet"]
                                     + list(extra), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.items = queue.Queue()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.proc.stdout:
            try:
                self.items.put((time.monotonic(), json.loads(line)))
            except json.JSONDecodeError:
                self.items.put((time.monotonic(), {"event": "unparsable", "message": line}))
        self.items.put(None)

    def wait_for(self, predicate, timeout):
        """The first item satisfying predicate within timeout: (time, item), or None."""
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            try:
                entry = self.items.get(timeout=left)
            except queue.Empty:
                return None
            if entry is None:
                return None
            if predicate(entry[1]):
                return entry

    def close(self):
        stop(self.proc, signal.SIGINT)
        return self.proc.stderr.read()
