#!/usr/bin/env python3
"""Plots the distance of a capture file (``rangekit capture``) or of a few seconds of a live
sensor with matplotlib (``apt install python3-matplotlib``).

    python3 plot.py capture run.sqlite
    python3 plot.py ls5 /dev/ttyUSB0 --seconds 5 --png out.png
"""

import argparse
import sys

import rangekit


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", choices=["capture", "uls", "ls5"])
    parser.add_argument("path", help="capture file or serial port")
    parser.add_argument("--seconds", type=float, default=5.0, help="live: how long to read")
    parser.add_argument("--png", help="write the figure here instead of showing it")
    options = parser.parse_args()
    try:
        import matplotlib

        if options.png:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot.py needs matplotlib: apt install python3-matplotlib", file=sys.stderr)
        return 2

    if options.source == "capture":
        samples = rangekit.capture.open(options.path).samples
    else:
        with getattr(rangekit, options.source).open(options.path) as drv, drv.stream() as stream:
            samples = stream.read(duration=options.seconds)
    valid = samples[(samples["flags"] & rangekit.FLAG_VALID) != 0]
    if len(valid) == 0:
        print("no distances to plot", file=sys.stderr)
        return 1
    figure, axes = plt.subplots()
    axes.plot(valid["time"] - valid["time"][0], valid["distance_m"] * 1000.0, ".", markersize=2)
    axes.set_xlabel("time (s)")
    axes.set_ylabel("distance (mm)")
    axes.set_title(options.path)
    if options.png:
        figure.savefig(options.png)
    else:
        plt.show()
    return 0


if __name__ == "__main__":
    sys.exit(main())
