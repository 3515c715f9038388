#!/usr/bin/env python3
"""Streams a ULS or LS5 into a CSV file, one row per sample, in blocks read as NumPy arrays.

    python3 stream_to_csv.py ls5 /dev/ttyUSB0 out.csv --duration 60
    python3 stream_to_csv.py uls /dev/ttyUSB1 out.csv --count 1000

Ctrl-C ends it cleanly (the rows read so far are kept). Link events (disconnected,
reconnected) are printed to stderr as they are met.
"""

import argparse
import sys
import time

import numpy

import rangekit


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("family", choices=["uls", "ls5"])
    parser.add_argument("port")
    parser.add_argument("out")
    parser.add_argument("--baud", type=int, default=115200)
    parser.add_argument("--duration", type=float, help="seconds (default: until Ctrl-C)")
    parser.add_argument("--count", type=int, help="samples")
    options = parser.parse_args()

    family = getattr(rangekit, options.family)
    written = 0
    deadline = time.monotonic() + options.duration if options.duration else None
    with family.open(options.port, baud=options.baud) as drv, drv.stream() as stream, open(options.out, "w") as out:
        out.write("time,distance_m,intensity,code,error,kind,flags\n")
        try:
            while options.count is None or written < options.count:
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    break
                want = 1000 if options.count is None else min(1000, options.count - written)
                block = stream.read(want, duration=min(left, 1.0) if left is not None else 1.0)
                for event in stream.take_events():
                    print(f"{event.kind}: {event.message}", file=sys.stderr)
                kinds = numpy.array(rangekit.sample_kinds)[block["kind"]]
                for row, kind in zip(block, kinds):
                    out.write(f"{row['time']:.6f},{row['distance_m']:.6f},{row['intensity']:.3f},{row['code']},"
                              f"{row['error']},{kind},{row['flags']}\n")
                written += len(block)
                if stream.finished:
                    break
        except KeyboardInterrupt:
            pass
    print(f"{written} samples written to {options.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
