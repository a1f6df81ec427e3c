"""What several ``plansynth reach`` commands share: the limits of the size options and
reading a result file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from plansynth.errors import InvalidProblem

#: plansynth.reach.problem's MAX_HORIZON and MAX_ORDER, repeated so that this module
#: loads without numpy (a test checks that they agree).
MAX_HORIZON_OPTION, MAX_ORDER_OPTION = 10_000, 50


def read_result(path: Path) -> dict[str, Any]:
    from plansynth.io import load_document

    doc, name = load_document(path)
    if not isinstance(doc, dict):
        raise InvalidProblem(name, "<document>", "a result file must be a JSON object")
    return doc
