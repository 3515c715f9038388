# Type stubs of the compiled module (python/src), re-exported by the package. They describe the
# module as built: the Sample fields of python/src/<family>/, and each family's submodule, a
# `<family>: Any` line python/CMakeLists.txt appends from the registration list (families.cmake).
from typing import Any, Dict, Iterator, List, Optional, Tuple, Union

import numpy

version: str
#: The NumPy record of Stream.read() and captures (docs/python.md):
#: time f8 (s since the Unix epoch, UTC), distance_m f8 (m, NaN when none),
#: intensity f8 (ULS pulse width ns / binning strength, NaN when none), pulses u4 (ULS look
#: down), code u2 (LS5 result code 0-65535), error i2 (ULS §10 number, 0 none), address i2
#: (-1 none), kind u1 (index in sample_kinds), flags u1 (FLAG_*), targets u1 (ULS binning).
sample_dtype: numpy.dtype
sample_kinds: List[str]
FLAG_VALID: int  # 0x01 the sample holds a distance
FLAG_NO_SIGNAL: int  # 0x02 LS5 65535 / ULS $ER,4
FLAG_NO_RESULT_YET: int  # 0x04 LS5 65534 / ULS $ER,5
FLAG_DERIVATIVE: int  # 0x08 LS5 distance derivative
FLAG_PRESENCE: int  # 0x10 ULS look down: target present
FLAG_PULSES_OVERFLOW: int  # 0x20 ULS look down: > 65535 pulses
FLAG_DEVICE_ERROR: int  # 0x40 ULS $ER,n
FLAG_SUSPECT: int  # 0x80 marked by the quality checks (Sample.suspect_reason)

def families() -> List[Dict[str, Any]]: ...  # [{name, title, channels: [{key, quantity, unit, description}]}]

class Sample:
    """One measurement (ULS or LS5); fields that do not apply are None."""
    @property
    def time(self) -> float: ...  # s since the Unix epoch (UTC), host receive time
    device: str  # "uls" | "ls5"
    source: str
    address: int  # -1 when the protocol has none
    @property
    def kind(self) -> str: ...  # averaging | binning | look-down | error | result | derivative
    @property
    def distance_m(self) -> Optional[float]: ...  # ULS, metres
    @property
    def pulse_width_ns(self) -> Optional[float]: ...  # ULS, nanoseconds (integer ps on the wire)
    @property
    def targets(self) -> List[Tuple[float, int]]: ...  # ULS binning: (distance_m, strength)
    @property
    def presence(self) -> Optional[bool]: ...
    @property
    def pulses_between_events(self) -> Optional[int]: ...  # 1-65535
    pulses_overflow: bool
    @property
    def device_error(self) -> Optional[int]: ...  # ULS §10 number
    @property
    def error_text(self) -> Optional[str]: ...
    @property
    def code(self) -> Optional[int]: ...  # LS5 0-50000, 65534, 65535
    @property
    def distance_mm(self) -> Optional[float]: ...  # LS5 formula 8.1
    @property
    def derivative_mm(self) -> Optional[float]: ...  # LS5 formula 8.2
    @property
    def signal(self) -> Optional[str]: ...  # ok | none_yet | lost
    @property
    def resolution_mm(self) -> Optional[float]: ...
    @property
    def suspect(self) -> bool: ...  # a value no real target gives at this rate (docs/reliability.md)
    @property
    def suspect_reason(self) -> Optional[str]: ...  # which check and why, or None
    @property
    def is_event(self) -> bool: ...  # False

class Event:
    """A link event: connected, disconnected, reconnected, bad_frame, lost_records, device_error, polling."""
    @property
    def time(self) -> float: ...
    @property
    def kind(self) -> str: ...
    message: str
    count: int  # records lost, for lost_records
    @property
    def is_event(self) -> bool: ...  # True

class Stream:
    def __iter__(self) -> Iterator[Union[Sample, Event]]: ...
    def __next__(self) -> Union[Sample, Event]: ...
    def __enter__(self) -> "Stream": ...
    def __exit__(self, *exc: Any) -> None: ...
    def next(self, timeout: Optional[float] = None) -> Optional[Union[Sample, Event]]: ...
    def read(self, n: Optional[int] = None, *, duration: Optional[float] = None) -> numpy.ndarray: ...
    def take_events(self) -> List[Event]: ...
    def stop(self) -> None: ...
    @property
    def finished(self) -> bool: ...
    @property
    def lost(self) -> int: ...
    @property
    def waiting(self) -> bool: ...

capture: Any
