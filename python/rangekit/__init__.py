"""rangekit for Python: each sensor family's driver and codec, the emulators and the captures
of the C++ library (docs/python.md).

* ``rangekit.<family>``, one module for each name of :func:`families`: ``open(port, ...)`` a
  driver (a context manager) with ``settings``, ``get_all()``, ``measure()`` and ``stream()``.
* :func:`families`: each family's name, title and channels, from the C++ registry.
* :class:`Sample`, :class:`Event`: what a stream's iterator yields, in order.
* :data:`sample_dtype`: the NumPy record of ``stream.read()`` and captures: ``time`` (s since
  the Unix epoch, UTC), ``distance_m`` (m, NaN when none), ``intensity`` (pulse width in ns or
  target strength, NaN when none), ``pulses``, ``code`` (result code), ``error`` (the device's
  error number), ``address``, ``kind`` (index in :data:`sample_kinds`), ``flags`` (``FLAG_*``),
  ``targets``.
* :mod:`rangekit.sim`: emulators for your own tests; :mod:`rangekit.capture`: capture files.
"""

import importlib

from . import _rangekit
from ._rangekit import (
    FLAG_DERIVATIVE,
    FLAG_DEVICE_ERROR,
    FLAG_NO_RESULT_YET,
    FLAG_NO_SIGNAL,
    FLAG_PRESENCE,
    FLAG_PULSES_OVERFLOW,
    FLAG_SUSPECT,
    FLAG_VALID,
    Event,
    Sample,
    Stream,
    sample_dtype,
    sample_kinds,
)
from . import errors, sim, capture
from ._families import FAMILIES, families
from .errors import RangekitError

# Each family's module, from the one list: import_module makes it rangekit.<name>.
for _name in FAMILIES:
    importlib.import_module(f".{_name}", __name__)

__version__ = _rangekit.version

__all__ = [
    *FAMILIES, "families", "sim", "capture", "errors", "RangekitError", "Sample", "Event", "Stream",
    "sample_dtype", "sample_kinds", "FLAG_VALID", "FLAG_NO_SIGNAL", "FLAG_NO_RESULT_YET",
    "FLAG_DERIVATIVE", "FLAG_PRESENCE", "FLAG_PULSES_OVERFLOW", "FLAG_DEVICE_ERROR",
    "FLAG_SUSPECT",
]
