"""SQLite captures (``rangekit capture``, docs/capture.md) as NumPy arrays.

>>> cap = rangekit.capture.open("run.sqlite")    # doctest: +SKIP
>>> cap.samples["distance_m"].mean()             # doctest: +SKIP
"""

from __future__ import annotations

import os
from typing import Any, List, Union

import numpy

from . import _rangekit

__all__ = ["Capture", "open", "sample_objects"]

_impl = _rangekit.capture


class Capture:
    """A capture read into memory in one pass (C++, without the GIL).

    ``samples``: every sample, a structured array of :data:`rangekit.sample_dtype`;
    ``events``: its link events (:class:`rangekit.Event`), in order.
    """

    def __init__(self, path: Union[str, "os.PathLike[str]"], device: str = ""):
        self.path = os.fspath(path)
        self.samples, self.events = _impl.read(self.path, device)

    def of_kind(self, kind: str) -> numpy.ndarray:
        """The samples of one kind (``"result"``, ``"averaging"``, ...: :data:`rangekit.sample_kinds`)."""
        return self.samples[self.samples["kind"] == list(_rangekit.sample_kinds).index(kind)]

    def dataframe(self) -> Any:
        """The samples as a pandas DataFrame (time as datetime64[ns, UTC], kind as its name).
        Needs pandas (``apt install python3-pandas``)."""
        try:
            import pandas
        except ImportError as missing:
            raise ImportError("Capture.dataframe() needs pandas; Capture.samples is the NumPy array") from missing
        frame = pandas.DataFrame(self.samples)
        frame["time"] = pandas.to_datetime(frame["time"], unit="s", utc=True)
        frame["kind"] = pandas.Categorical.from_codes(frame["kind"], list(_rangekit.sample_kinds))
        return frame

    def __len__(self) -> int:
        return len(self.samples)

    def __repr__(self) -> str:
        return f"<rangekit.capture.Capture {self.path}: {len(self.samples)} samples, {len(self.events)} events>"


def sample_objects(path: Union[str, "os.PathLike[str]"], device: str = "") -> List[Any]:
    """Every sample of a capture as a :class:`rangekit.Sample`, with all its fields and its
    ``reading``; slower than :func:`open`'s array, for a look at single records."""
    return list(_impl.samples(os.fspath(path), device))


def open(path: Union[str, "os.PathLike[str]"], device: str = "") -> Capture:
    """Reads a capture file; ``device``, a family's name (:func:`rangekit.families`), keeps that
    family's samples."""
    return Capture(path, device)
