"""The exceptions rangekit raises.

Every error of the C++ library arrives as a :class:`RangekitError` (or a subclass) with

* ``code``: the library's error code name (``"out_of_range"``, ``"device_error"``,
  ``"timeout"``, ...),
* ``number``: the device's error number for ``device_error`` (e.g. 31), else None,
* ``text``: its family's text for that number, from the sensor's document (e.g. "Already
  Measuring"), else None.

Subclasses also derive from the built-in exception a Python user would expect, so
``except ValueError`` catches a refused setting and ``except TimeoutError`` a silent unit.
"""

from __future__ import annotations

from typing import Optional

__all__ = [
    "RangekitError",
    "DeviceError",
    "SettingError",
    "NoReply",
    "LinkError",
    "DecodeError",
    "UnsupportedError",
]


class RangekitError(Exception):
    """Base of every rangekit error."""

    def __init__(self, message: str, code: str = "", number: Optional[int] = None, text: Optional[str] = None):
        super().__init__(message)
        self.message = message
        self.code = code
        self.number = number
        self.text = text


class DeviceError(RangekitError):
    """The device answered with an error number (see ``number`` and ``text``)."""


class SettingError(RangekitError, ValueError):
    """A name or value refused before anything was sent (unknown name, out of range, wrong form)."""


class NoReply(RangekitError, TimeoutError):
    """Nothing answered in time (port, baud rate, address?)."""


class LinkError(RangekitError, OSError):
    """The port could not be opened, or the link went away."""


class DecodeError(RangekitError, ValueError):
    """Bytes that are not a frame or packet of the protocol."""


class UnsupportedError(RangekitError):
    """Not available here (firmware version, a stream holding the line, ...)."""
