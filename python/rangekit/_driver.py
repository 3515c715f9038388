"""What every family's driver shares: settings, context manager, close."""

from __future__ import annotations

from typing import Any, Dict, Iterable, Mapping, Optional, Tuple, Union

from ._settings import Settings, pairs_of


class BaseDriver:
    """A driver over the C++ one; use it as a context manager to close the port."""

    def __init__(self, impl: Any, names: Iterable[str]):
        self._impl = impl
        #: The settings by name, as a mutable mapping (see :class:`rangekit._settings.Settings`).
        self.settings = Settings(self, names)

    @property
    def port(self) -> str:
        """The port path this driver opened."""
        return self._impl.port

    def get(self, name: str) -> Any:
        """One setting's value (int, float, list of numbers, or str)."""
        return self._impl.get(name)

    def set(self, name: Optional[str] = None, value: Any = None, /, **values: Any) -> None:
        """``set("prf-hz", 2000)`` or ``set(prf_hz=2000, mode="binning")`` (underscores read as dashes).

        Every value is checked before anything is sent; then they are written in order.
        """
        pairs = [] if name is None else [(name, value)]
        pairs += [(key.replace("_", "-"), item) for key, item in values.items()]
        self.set_many(pairs)

    def set_many(self, values: Union[Mapping[str, Any], Iterable[Tuple[str, Any]]]) -> None:
        """Several settings: every value checked before the first is sent, then written in order."""
        self._impl.set_many(pairs_of(values))

    def get_all(self) -> Dict[str, Any]:
        """Every readable setting as a dict, in table order; the unit is in the name (``prf-hz``) or
        in :func:`setting_units`."""
        return self._impl.get_all()

    def info(self) -> Dict[str, Any]:
        """The unit's identity."""
        return self._impl.info()

    def measure(self) -> Any:
        """One measurement as a :class:`rangekit.Sample`."""
        return self._impl.measure()

    def start_measuring(self) -> None:
        self._impl.start_measuring()

    def stop_measuring(self) -> None:
        self._impl.stop_measuring()

    def save(self) -> None:
        """The settings into the device's non-volatile memory."""
        self._impl.save()

    def close(self) -> None:
        """Closes the port (a running stream ends first)."""
        self._impl.close()

    def __enter__(self) -> "BaseDriver":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<{type(self).__module__}.{type(self).__name__} on {self.port}>"
