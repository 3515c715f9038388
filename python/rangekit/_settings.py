"""The ``settings`` mapping both drivers share: ``drv.settings["prf-hz"] = 2000``."""

from __future__ import annotations

from typing import Any, Iterable, Iterator, List, Mapping, MutableMapping, Tuple, Union


def value_text(value: Any) -> str:
    """A Python value as the text `rangekit ... set NAME=VALUE` takes."""
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, (list, tuple)):
        return ",".join(value_text(item) for item in value)
    if isinstance(value, float):
        return repr(value)
    return str(value)


def pairs_of(values: Union[Mapping[str, Any], Iterable[Tuple[str, Any]]]) -> List[Tuple[str, str]]:
    items = values.items() if isinstance(values, Mapping) else values
    return [(str(name), value_text(value)) for name, value in items]


class Settings(MutableMapping):
    """A driver's settings by the names of ``rangekit <family> get``.

    Reading a key asks the device; assigning checks the value before anything is sent
    (:class:`rangekit.errors.SettingError` when refused) and writes it. ``update()`` checks
    every value first, then writes them in order. Iterating lists the names.
    """

    def __init__(self, driver: Any, names: Iterable[str]):
        self._driver = driver
        self._names = list(names)

    def __getitem__(self, name: str) -> Any:
        return self._driver.get(name)

    def __setitem__(self, name: str, value: Any) -> None:
        self._driver.set(**{name: value})

    def __delitem__(self, name: str) -> None:
        raise TypeError("a device setting cannot be deleted")

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def update(self, *args: Any, **kwargs: Any) -> None:  # type: ignore[override]
        pairs: List[Tuple[str, Any]] = []
        for values in args:
            pairs.extend(values.items() if isinstance(values, Mapping) else values)
        pairs.extend(kwargs.items())
        self._driver.set_many(pairs)
