"""rangekit for Python: the ULS and LS5 drivers, codecs, emulators and captures of the
C++ library (docs/python.md).

* :mod:`rangekit.uls`, :mod:`rangekit.ls5`: ``open(port, ...)`` a driver (a context
  manager) with ``settings``, ``get_all()``, ``measure()`` and ``stream()``.
* :class:`Sample`, :class:`Event`: what a stream's iterator yields, in order.
* :data:`sample_dtype`: the NumPy record of ``stream.read()`` and captures: ``time`` (s since
  the Unix epoch, UTC), ``distance_m`` (m, NaN when none), ``intensity`` (ULS pulse width in ns
  or binning strength, NaN when none), ``pulses``, ``code`` (LS5 result code), ``error`` (ULS
  §10 number), ``address``, ``kind`` (index in :data:`sample_kinds`), ``flags`` (``FLAG_*``),
  ``targets``.
* :mod:`rangekit.sim`: emulators for your own tests; :mod:`rangekit.capture`: capture files.
"""

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
from . import errors, uls, ls5, sim, capture
from .errors import RangekitError

__version__ = _rangekit.version

__all__ = [
    "uls", "ls5", "sim", "capture", "errors", "RangekitError", "Sample", "Event", "Stream",
    "sample_dtype", "sample_kinds", "FLAG_VALID", "FLAG_NO_SIGNAL", "FLAG_NO_RESULT_YET",
    "FLAG_DERIVATIVE", "FLAG_PRESENCE", "FLAG_PULSES_OVERFLOW", "FLAG_DEVICE_ERROR",
    "FLAG_SUSPECT",
]
