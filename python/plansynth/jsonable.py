"""Plain JSON values for the records results carry (options, counters, timings), shared
by the grid and the reach results (STYLE.md, point 1: a result carries the record of
how it was found, and that record is written as JSON).

>>> import enum, numpy as np
>>> class Colour(enum.Enum):
...     RED = "red"
>>> jsonable({"n": np.int64(3), "x": (1.5, None), 2: Colour.RED, "p": __import__("pathlib").Path("a/b")})
{'n': 3, 'x': [1.5, None], '2': 'red', 'p': 'a/b'}
>>> jsonable(object())[:8]
'<object '
"""

from __future__ import annotations

import enum
from pathlib import Path
from typing import Any

__all__ = ["jsonable"]


def jsonable(value: Any) -> Any:
    """``value`` with plain JSON types only: dictionaries (keys as strings) and lists,
    enums as their values, options values as their ``to_dict()``, numpy scalars as Python numbers, paths as strings; anything
    else as its ``repr``."""
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "to_dict") and callable(value.to_dict):  # an options value (NativeOptions)
        return jsonable(value.to_dict())
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if hasattr(value, "item") and callable(value.item):  # a numpy scalar
        return value.item()
    return repr(value)
