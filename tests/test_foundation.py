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


def test_a_key_written_twice_is_rejected_in_yaml_and_json(tmp_path):
    from plansynth.io import load_document

    y = tmp_path / "p.yaml"
    y.write_text("grid: [3, 3]\nrobot: {start: [0, 0]}\nrobot: {start: [1, 1]}\n")
    with pytest.raises(InvalidProblem, match=r"p\.yaml: robot: duplicated key \(line 3\)"):
        load_document(y)
    j = tmp_path / "p.json"
    j.write_text('{"grid": [3, 3], "grid": [4, 4]}')
    with pytest.raises(InvalidProblem, match=r"p\.json: grid: duplicated key"):
        load_document(j)
    ok = tmp_path / "ok.yaml"
    ok.write_text("a: {b: 1}\nc: [1, {d: 2}]\n")
    assert load_document(ok)[0] == {"a": {"b": 1}, "c": [1, {"d": 2}]}
