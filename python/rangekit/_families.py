"""The families: one module each (``rangekit.<name>``), named and ordered as the registration
list, families.cmake, which the compiled module's registry is filled from; so there is no
second list here to keep in step (python/tests/test_families.py checks the two agree)."""

from __future__ import annotations

from typing import Any, Dict, List, Tuple

from . import _rangekit


def families() -> List[Dict[str, Any]]:
    """Every family, as the C++ registry describes it: ``name`` (its module ``rangekit.<name>``
    and its samples' ``device``), ``title``, and ``channels``, each a dict of ``key`` (the
    field or column name), ``quantity``, ``unit`` (``"m"``, ``"mm"``, ``""`` for a count) and
    ``description``."""
    return list(_rangekit.families())


#: The families' names, in registration order.
FAMILIES: Tuple[str, ...] = tuple(family["name"] for family in families())
