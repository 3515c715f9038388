"""LTI ULS laser rangefinders: driver and codec (docs/host-uls.md, docs/python.md).

>>> import rangekit
>>> with rangekit.uls.open("/dev/ttyUSB0") as drv:          # doctest: +SKIP
...     drv.settings["prf-hz"] = 2000
...     for item in drv.stream():
...         print(item)
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Union

from . import _rangekit
from ._driver import BaseDriver

_impl = _rangekit.uls
# rangekit.sim.uls(): the emulator's configuration port (`rangekit sim uls --config-port`), by file name.
_SIM_CONFIG_PORT = "uls-config"

__all__ = ["open", "Driver", "setting_ranges", "decode_line", "error_text", "readable_names", "writable_names"]


class Driver(BaseDriver):
    """A ULS unit (rangekit::uls::Driver): requests matched to replies, a timeout per call,
    one retry for gets, a stream that reconnects when the port comes back.

    Setting names are those of ``rangekit uls get``: the unit is in the name (``prf-hz``,
    ``short-gate-m``, ``fault-current-ma``); distances are in metres whatever MU is.
    """

    def __init__(self, impl: Any):
        super().__init__(impl, _impl.readable_names())

    def status(self) -> Dict[str, Any]:
        """US decoded into its bits (§8 Get Unit Status)."""
        return self._impl.status()

    def stream(
        self,
        mode: str = "automatic",
        *,
        check_quality: bool = True,
        max_speed: Optional[float] = None,
        drop_suspect: bool = False,
    ) -> "_rangekit.Stream":
        """Starts measuring (GO unless already measuring) and returns the stream.

        ``mode``: ``automatic`` (continuous lines, falling back to polling with BM when none
        arrive), ``continuous`` or ``polled``. Iterate it for :class:`rangekit.Sample` and
        :class:`rangekit.Event` objects, or ``read(n)`` / ``read(duration=s)`` NumPy arrays.
        Ending it leaves the unit as found (U86).

        Each sample is checked as ``rangekit uls stream`` does (docs/reliability.md): a distance
        further from the running median than ``max_speed`` m/s allows (default 25), or a pulse
        width off by more than a factor 2, gets ``suspect`` (and ``FLAG_SUSPECT`` in arrays);
        ``drop_suspect`` leaves such samples out, ``check_quality=False`` turns the checks off.
        """
        return self._impl.stream(mode, check_quality=check_quality, max_speed=max_speed, drop_suspect=drop_suspect)


def open(port: str, baud: int = 115200, address: Optional[Union[str, int]] = None, timeout: float = 1.0) -> Driver:
    """Opens a ULS on ``port`` (8N1 at ``baud``, §9).

    ``address``: the RS-485 unit address, 0x30-0xEF, as a character (``"A"``), ``"0x41"`` or an
    int; None talks the ``$`` protocol. ``timeout``: seconds to wait for each reply.
    """
    if isinstance(address, int):
        address = hex(address)
    return Driver(_impl.open(port, baud, address, timeout))


def decode_line(
    line: bytes, *, mode: str = "averaging", display: str = "range", units: str = "metres", time_between_events: bool = False
) -> "_rangekit.Sample":
    """Decodes one measurement line (``b"$BM,12.345\\r"``) into a :class:`rangekit.Sample`.

    A line cannot be read without the unit's settings (U11): ``mode`` (averaging, binning,
    look-down), ``display`` (range, range-and-intensity, intensity), ``units`` (metres, feet) and
    ``time_between_events`` (TB). Raises :class:`rangekit.errors.DecodeError` on bad bytes.
    """
    return _impl.decode_line(line, mode=mode, display=display, units=units, time_between_events=time_between_events)


def error_text(number: int) -> str:
    """The §10 text of a ULS error number ("not listed in §10" for others)."""
    return _impl.error_text(number)


def readable_names() -> List[str]:
    """The setting names ``get`` accepts, in table order."""
    return list(_impl.readable_names())


def writable_names() -> List[str]:
    """The setting names ``set`` accepts."""
    return [name.strip() for name in _impl.writable_names().split(",")]


def setting_ranges() -> Dict[str, str]:
    """Every setting name and what ``drv.settings[name] = value`` accepts (§8's ranges; distances in metres whatever MU is)."""
    return dict(_impl.setting_ranges())


# help(rangekit.uls) lists every setting with its range, from the same table the CLI uses.
__doc__ = (__doc__ or "") + "\nSettings (name: what set accepts):\n\n" + "\n".join(
    f"    {name}: {allowed}" for name, allowed in setting_ranges().items()
) + "\n"
