"""Prizma LS5 laser triangulation sensors: driver and codec (docs/host-ls5.md, docs/python.md).

>>> import rangekit
>>> with rangekit.ls5.open("/dev/ttyUSB0", address=1) as drv:   # doctest: +SKIP
...     drv.settings["thinning"] = 4
...     block = drv.stream().read(1000)
"""

from __future__ import annotations

from typing import Any, Dict, Optional

from . import _rangekit
from ._driver import BaseDriver

_impl = _rangekit.ls5

__all__ = ["open", "Driver", "setting_ranges", "parse_udp", "setting_units"]


class Driver(BaseDriver):
    """An LS5 (rangekit::ls5::Driver): every command of table 9.1 and parameter of table 9.2.

    Setting names are those of ``rangekit ls5 get`` (``thinning``, ``period-ms``, ...); their
    units are in :func:`setting_units`. While a stream runs it holds the line and other calls
    are refused (:class:`rangekit.errors.UnsupportedError`).
    """

    def __init__(self, impl: Any):
        super().__init__(impl, setting_units().keys())

    def restore_defaults(self) -> None:
        """DF: factory parameters, in RAM until :meth:`save` (L27)."""
        self._impl.restore_defaults()

    def stream(
        self,
        thinning: Optional[int] = None,
        reconnect_interval: float = 0.5,
        silence_timeout: float = 3.0,
        *,
        check_quality: bool = True,
        max_speed: Optional[float] = None,
        drop_suspect: bool = False,
        queue_capacity: int = 65536,
    ) -> "_rangekit.Stream":
        """Starts the record stream (ST) and returns it.

        ``thinning``: n of §8.4 (0-255), written first when given. After ``silence_timeout``
        seconds without a record the sensor is taken for gone (a ``disconnected`` event) and
        asked again every ``reconnect_interval`` seconds (``reconnected``).

        Each record is checked as ``rangekit ls5 stream`` does (docs/reliability.md): one further
        from the running median than ``max_speed`` m/s allows (default: the range a second) gets
        ``suspect`` (and ``FLAG_SUSPECT`` in arrays); ``drop_suspect`` leaves such records out,
        ``check_quality=False`` turns the checks off.

        ``queue_capacity``: records kept for a reader that falls behind (1 or more); beyond it the
        oldest are dropped and a ``lost_records`` event with their ``count`` comes where they were.
        """
        return self._impl.stream(
            thinning,
            reconnect_interval,
            silence_timeout,
            check_quality=check_quality,
            max_speed=max_speed,
            drop_suspect=drop_suspect,
            queue_capacity=queue_capacity,
        )


def open(port: str, baud: int = 115200, address: int = 1, timeout: float = 0.5) -> Driver:
    """Opens an LS5 on ``port`` (8N1 at ``baud``; factory settings 115200, address 1).

    ``address``: the network address 1-255 (0 broadcasts: nothing answers). ``timeout``:
    seconds per attempt.
    """
    return Driver(_impl.open(port, baud, address, timeout))


def parse_udp(packet: bytes) -> Dict[str, Any]:
    """Decodes one 512-byte Ethernet datagram (§10.1).

    Returns ``records`` (a NumPy array of 168 rows: ``code``, ``state``, ``distance_mm`` by
    formula 10.1, NaN when not a measured in-range distance), ``serial_number``,
    ``lower_boundary_mm``, ``range_mm`` and ``counter``. Raises DecodeError on a bad size
    or checksum.
    """
    return _impl.parse_udp(packet)


def setting_units() -> Dict[str, str]:
    """Every setting name and its unit (``"ms"``, ``"mm"``, ``"code"``, ``""``)."""
    return dict(_impl.setting_units())


def setting_ranges() -> Dict[str, str]:
    """Every setting name and what ``drv.settings[name] = value`` accepts (table 9.2, newest firmware; ``-mm`` values scale with the sensor's range)."""
    return dict(_impl.setting_ranges())


# help(rangekit.ls5) lists every setting with its range, from the same table the CLI uses.
__doc__ = (__doc__ or "") + "\nSettings (name: what set accepts):\n\n" + "\n".join(
    f"    {name}: {allowed}" for name, allowed in setting_ranges().items()
) + "\n"
