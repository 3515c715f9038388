#!/usr/bin/env python3
"""A test-rig script: sets up an LS5, checks it is the sensor the rig expects, and logs a
minute of measurements with their statistics.

    python3 rig.py /dev/ttyUSB0 --serial 157 --range-mm 100 --log rig.csv

Exit status 0 when the sensor is the expected one and nothing was lost, 1 otherwise.
Try it on the emulator: `rangekit sim ls5 --port /tmp/ls5` in another terminal, then
`python3 rig.py /tmp/ls5`.
"""

import argparse
import sys

import numpy

import rangekit


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("port")
    parser.add_argument("--address", type=int, default=1)
    parser.add_argument("--serial", type=int, help="the serial number this rig expects")
    parser.add_argument("--range-mm", type=float, help="the measurement range this rig expects")
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--log", default="rig.csv")
    options = parser.parse_args()

    with rangekit.ls5.open(options.port, address=options.address) as drv:
        info = drv.info()
        print(f"LS5 {info['version']} s/n {info['serial_number']}, range {info['range_mm']} mm")
        if options.serial is not None and info["serial_number"] != options.serial:
            print(f"wrong sensor: s/n {info['serial_number']}, expected {options.serial}", file=sys.stderr)
            return 1
        if options.range_mm is not None and abs(info["range_mm"] - options.range_mm) > 1e-6:
            print(f"wrong model: range {info['range_mm']} mm, expected {options.range_mm}", file=sys.stderr)
            return 1
        # The rig's settings: every value is checked before the first is written.
        drv.set_many({"pre-filter": "median", "median-points": 5, "thinning": 1})
        print("settings:", {name: drv.settings[name] for name in ("pre-filter", "median-points", "thinning")})

        with drv.stream() as stream:
            block = stream.read(duration=options.seconds)
            events = stream.take_events()
            lost = stream.lost
    numpy.savetxt(options.log, numpy.column_stack([block["time"], block["code"], block["distance_m"] * 1000.0]),
                  delimiter=",", header="time,code,distance_mm", comments="", fmt=["%.6f", "%d", "%.4f"])
    valid = block[(block["flags"] & rangekit.FLAG_VALID) != 0]
    print(f"{len(block)} samples in {options.seconds} s, {len(valid)} with a distance, {lost} lost")
    if len(valid):
        millimetres = valid["distance_m"] * 1000.0
        print(f"distance: mean {millimetres.mean():.4f} mm, std {millimetres.std():.4f} mm, "
              f"min {millimetres.min():.4f}, max {millimetres.max():.4f}")
    for event in events:
        print(f"event: {event.kind} {event.message}")
    return 0 if lost == 0 and not any(e.kind == "disconnected" for e in events) else 1


if __name__ == "__main__":
    sys.exit(main())
