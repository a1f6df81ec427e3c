import pytest

from plansynth import Budget, InvalidProblem
from plansynth._core import core_version
from plansynth.io import Fields


def test_core_builds_and_loads():
    assert core_version() == "0.1.0"


def test_fields_names_file_field_and_reason():
    with pytest.raises(InvalidProblem, match=r"f\.yaml: robot\.colour: unknown key"):
        Fields({"colour": 1}, "f.yaml", "robot").reject_unknown({"start"})


def test_budget_rejects_nonpositive_time():
    with pytest.raises(ValueError):
        Budget(seconds=0)
