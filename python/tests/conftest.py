"""Fixtures for the rangekit Python tests: emulators started through rangekit.sim
(the CLI's `rangekit sim`, on ptys in a temporary directory), stopped afterwards.
Run through ctest (rangekit_python_tests) with PYTHONPATH=build/python."""

import os
import select

import pytest

import rangekit


class SilentLine:
    """A pty with nothing behind it: `path` for the driver; any byte the driver sent would
    be readable on the master side, so `written()` tells whether anything was."""

    def __init__(self, master, slave):
        self.master = master
        self.path = os.ttyname(slave)

    def written(self):
        readable, _, _ = select.select([self.master], [], [], 0)
        return readable != []


@pytest.fixture
def silent_line():
    master, slave = os.openpty()
    try:
        yield SilentLine(master, slave)
    finally:
        os.close(master)
        os.close(slave)


@pytest.fixture
def uls_unit():
    with rangekit.sim.uls() as unit:
        yield unit


LS5_ARGUMENTS = ["--model", "0/100", "--version", "LS5.12.0", "--serial", "157"]
# A surface 25 mm into the 100 mm range, without noise (docs/emulator-ls5.md "Scene").
LS5_SCENE = {"target": {"position_mm": 25.0, "noise_mm": 0.0}}


@pytest.fixture
def ls5_unit():
    # LS5.12.0, lower boundary 0, range 100 mm: the sensor of the CLI's own LS5 tests.
    with rangekit.sim.ls5(scene=LS5_SCENE, arguments=LS5_ARGUMENTS) as unit:
        yield unit


def first_event(stream):
    """The stream's next event, passing the samples before it (in order, as the iterator yields them)."""
    for item in stream:
        if item.is_event:
            return item
    raise AssertionError("the stream ended without an event")


def samples(stream, count):
    """The next `count` samples of the iterator, events left out."""
    found = []
    for item in stream:
        if not item.is_event:
            found.append(item)
            if len(found) == count:
                return found
    raise AssertionError(f"the stream ended after {len(found)} samples")
