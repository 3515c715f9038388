#!/usr/bin/env python3
"""Benchmark of the Python package against its goals (figures in docs/python.md).

1. An LS5 at 1 kHz (period 1 ms, thinning 1, 115200 baud) read for 10 s through
   ``stream.read()``, against a pyserial reader written in plain Python (Debian's
   python3-serial) parsing the same stream (``#01ST<CR>``, records ``!ddddd<CR>``, formula 8.1),
   in one run: two identical emulators (same model, scene and seed), one reader process each,
   both at the same time. Each process reports the CPU time (user + system, every thread) it
   spent streaming and the records it got; the emulators count what they measured.
2. A capture of N samples (default 10 million, written with SQL into a capture made by
   ``rangekit capture``) read into NumPy with ``rangekit.capture.open``.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py [--seconds 10] [--capture-samples 10000000]
"""

import argparse
import json
import os
import resource
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time

import rangekit

RANGE_MM = 100.0
LS5_ARGUMENTS = ["--model", "0/100", "--version", "LS5.12.0", "--seed", "7"]
SCENE = {"target": {"position_mm": 40.0, "speed_mm_per_s": 1.0}}


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def read_with_rangekit(port, seconds):
    with rangekit.ls5.open(port) as drv:
        stream = drv.stream(thinning=1)
        start_cpu, start = cpu_seconds(), time.monotonic()
        block = stream.read(duration=seconds)
        cpu, wall = cpu_seconds() - start_cpu, time.monotonic() - start
        events = [event.kind for event in stream.take_events()]
        lost = stream.lost
        stream.stop()
    valid = int(((block["flags"] & rangekit.FLAG_VALID) != 0).sum())
    return {"reader": "rangekit stream.read()", "records": len(block), "valid": valid, "lost": lost,
            "events": events, "cpu_s": cpu, "wall_s": wall}


def read_with_pyserial(port, seconds):
    """What a user writes by hand: pyserial, split on CR, int() the code, formula 8.1."""
    import serial

    link = serial.Serial(port, 115200, timeout=0.1)
    link.write(b"#01ST\r")
    start_cpu, start = cpu_seconds(), time.monotonic()
    samples = []
    buffer = b""
    while time.monotonic() - start < seconds:
        buffer += link.read(link.in_waiting or 1)
        *lines, buffer = buffer.split(b"\r")
        for line in lines:
            if len(line) == 6 and line[:1] == b"!":
                code = int(line[1:])
                distance = RANGE_MM * code / 50000 if code <= 50000 else None
                samples.append((time.time(), code, distance))
    cpu, wall = cpu_seconds() - start_cpu, time.monotonic() - start
    link.write(b"#01SB\r")
    link.close()
    valid = sum(1 for sample in samples if sample[2] is not None)
    return {"reader": "pyserial, plain Python", "records": len(samples), "valid": valid, "cpu_s": cpu, "wall_s": wall}


def serial_benchmark(seconds):
    units = [rangekit.sim.ls5(scene=SCENE, arguments=LS5_ARGUMENTS) for _ in range(2)]
    try:
        for unit in units:
            unit.start()
            with rangekit.ls5.open(unit.port) as drv:
                drv.set_many({"period-ms": 1.0, "thinning": 1})  # §8.4: 1 kHz, every result
        before = [unit.command({"cmd": "outputs"}).get("measurements", 0) for unit in units]
        readers = [
            subprocess.Popen([sys.executable, __file__, "--child", mode, "--port", unit.port, "--seconds", str(seconds)],
                             stdout=subprocess.PIPE, text=True)
            for mode, unit in zip(("rangekit", "pyserial"), units)
        ]
        results = [json.loads(reader.communicate()[0]) for reader in readers]
        after = [unit.command({"cmd": "outputs"}).get("measurements", 0) for unit in units]
        for result, first, last in zip(results, before, after):
            result["emulator_measurements"] = last - first
        return results
    finally:
        for unit in units:
            unit.close()


def make_capture(path, count):
    """A capture made by ``rangekit capture`` (one LS5 sample), multiplied to ``count`` samples with SQL."""
    with rangekit.sim.ls5(arguments=LS5_ARGUMENTS) as unit:
        subprocess.run([rangekit.sim.cli_path(), "capture", "--out", path, "--ls5", unit.port, "--count", "1",
                        "--quiet"], check=True, capture_output=True)
    database = sqlite3.connect(path)
    database.execute(
        "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < ?) "
        "INSERT INTO samples(session, time_ns, device, source, address, kind, code, distance_mm, signal, "
        "resolution_mm) SELECT s.session, s.time_ns + i * 1000000, s.device, s.source, s.address, s.kind, "
        "i % 50001, (i % 50001) * 100.0 / 50000, 'ok', s.resolution_mm FROM n, (SELECT * FROM samples LIMIT 1) s",
        (count - 1,))
    database.commit()
    database.close()


def timed(call):
    """(result, wall seconds, CPU seconds of this process, every thread)."""
    start_cpu, start = cpu_seconds(), time.monotonic()
    result = call()
    return result, time.monotonic() - start, cpu_seconds() - start_cpu


def sqlite3_baseline(path):
    """The baseline: Python's sqlite3 module stepping through the columns rangekit reads, in seq
    order, one Python tuple a row (what a user would write without the package; the rows are
    only counted, not kept nor converted to NumPy, so the baseline does less than rangekit)."""
    database = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        return sum(1 for _ in database.execute(
            "SELECT seq, time_ns, device, source, address, kind, distance_m, pulse_width, targets, presence, "
            "pulses_between_events, device_error, code, distance_mm, signal, derivative_mm, resolution_mm, "
            "suspect, suspect_reason FROM samples ORDER BY seq"))
    finally:
        database.close()


SQLITE_FLOOR_SQL = (
    "SELECT max(time_ns + coalesce(address, 0) + length(kind) + coalesce(distance_m, 0) + coalesce(pulse_width, 0) "
    "+ length(coalesce(targets, '')) + coalesce(presence, 0) + coalesce(pulses_between_events, 0) "
    "+ coalesce(device_error, 0) + coalesce(code, 0) + coalesce(distance_mm, 0) + length(coalesce(signal, '')) "
    "+ coalesce(derivative_mm, 0) + coalesce(resolution_mm, 0) + coalesce(suspect, 0) + length(device) "
    "+ length(source) + length(coalesce(suspect_reason, ''))) FROM samples")


def sqlite_floor(path):
    """SQLite alone, in C (the sqlite3 shell, file mapped): every column rangekit reads decoded on
    every row and folded into one number; what any reader built on SQLite's row engine pays.
    (seconds, CPU seconds), or None without the sqlite3 shell (Debian package sqlite3)."""
    shell = shutil.which("sqlite3")
    if not shell:
        return None
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    subprocess.run([shell, "-readonly", path, "PRAGMA mmap_size = 4294967296", SQLITE_FLOOR_SQL], check=True,
                   capture_output=True)
    seconds = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return seconds, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def capture_benchmark(count, keep_path=None):
    """The capture read by rangekit.capture.open and, in the same run, by the sqlite3 baseline."""
    directory = None
    if keep_path and os.path.exists(keep_path):
        path = keep_path
    else:
        if keep_path:
            path = keep_path
        else:
            directory = tempfile.mkdtemp(prefix="rangekit-bench-")
            path = os.path.join(directory, "bench.sqlite")
        make_capture(path, count)
    try:
        with open(path, "rb") as warm:  # both readers start with the file in the page cache
            while warm.read(1 << 24):
                pass
        capture, seconds, cpu = timed(lambda: rangekit.capture.open(path))
        rows, base_seconds, base_cpu = timed(lambda: sqlite3_baseline(path))
        floor = sqlite_floor(path)
    finally:
        if directory:
            shutil.rmtree(directory)
    return {"samples": len(capture), "seconds": seconds, "cpu_s": cpu, "samples_per_s": len(capture) / seconds,
            "baseline_rows": rows, "baseline_seconds": base_seconds, "baseline_cpu_s": base_cpu,
            "baseline_per_s": rows / base_seconds, "floor": floor}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--capture-samples", type=int, default=10_000_000)
    parser.add_argument("--capture-file", help="keep the capture here and reuse it when it exists")
    parser.add_argument("--capture-only", action="store_true", help="skip the serial benchmark")
    parser.add_argument("--child", choices=["rangekit", "pyserial"], help=argparse.SUPPRESS)
    parser.add_argument("--port", help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.child:
        reader = read_with_rangekit if options.child == "rangekit" else read_with_pyserial
        print(json.dumps(reader(options.port, options.seconds)))
        return 0

    if options.capture_only:
        results = []
    else:
        results = serial_benchmark(options.seconds)
    for result in results:
        print(f"{result['reader']:24} {result['records']:6} records ({result['valid']} valid) in "
              f"{result['wall_s']:.2f} s, emulator measured {result['emulator_measurements']}, "
              f"CPU {result['cpu_s']:.3f} s ({100 * result['cpu_s'] / result['wall_s']:.1f} % of a core)"
              + (f", lost {result['lost']}, events {result['events']}" if "lost" in result else ""))
    if results:
        ratio = results[0]["cpu_s"] / results[1]["cpu_s"]
        print(f"rangekit CPU / pyserial CPU = {ratio:.3f} (goal: at most 1/3)")
    if options.capture_samples > 0:
        capture = capture_benchmark(options.capture_samples, options.capture_file)
        rate = capture["samples_per_s"] / 1e6
        print(f"capture: {capture['samples']} samples into NumPy in {capture['seconds']:.2f} s "
              f"(CPU {capture['cpu_s']:.2f} s) = {rate:.2f} M samples/s; goal at least 5: "
              f"{'met' if rate >= 5 else 'MISSED'}")
        print(f"baseline, Python sqlite3 stepping through the same columns: {capture['baseline_rows']} rows in "
              f"{capture['baseline_seconds']:.2f} s (CPU {capture['baseline_cpu_s']:.2f} s) = "
              f"{capture['baseline_per_s'] / 1e6:.2f} M rows/s; rangekit / baseline = "
              f"{capture['samples_per_s'] / capture['baseline_per_s']:.2f}")
        if capture["floor"]:
            floor_seconds, floor_cpu = capture["floor"]
            print(f"floor, the sqlite3 shell decoding the same columns (C, no output): {floor_seconds:.2f} s "
                  f"(CPU {floor_cpu:.2f} s) = {capture['baseline_rows'] / floor_seconds / 1e6:.2f} M rows/s; "
                  f"rangekit / floor = {capture['samples_per_s'] * floor_seconds / capture['baseline_rows']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
