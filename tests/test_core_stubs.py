"""python/plansynth/_core.pyi against the compiled module it describes: the same public
names, the same parameters (names, order, which have defaults, and the defaults), and
every parameter and return typed. The signatures of the compiled module come from the
``__text_signature__`` PyO3 writes from each ``#[pyo3(signature = ...)]``."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import pytest

from plansynth import _core

STUB = Path(__file__).resolve().parents[1] / "python" / "plansynth" / "_core.pyi"


def _stub() -> dict[str, ast.FunctionDef | ast.ClassDef]:
    tree = ast.parse(STUB.read_text(encoding="utf-8"))
    return {
        n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef)) and not n.name.startswith("_")
    }


def _methods(cls: ast.ClassDef) -> dict[str, ast.FunctionDef]:
    return {n.name: n for n in cls.body if isinstance(n, ast.FunctionDef)}


def _stub_params(fn: ast.FunctionDef) -> list[tuple[str, object]]:
    """(name, default or inspect.Parameter.empty) of each parameter, ``self``/``cls`` left out."""
    args = fn.args.posonlyargs + fn.args.args
    defaults = [inspect.Parameter.empty] * (len(args) - len(fn.args.defaults)) + [
        ast.literal_eval(d) for d in fn.args.defaults
    ]
    out = [(a.arg, d) for a, d in zip(args, defaults)]
    out += [
        (a.arg, inspect.Parameter.empty if d is None else ast.literal_eval(d))
        for a, d in zip(fn.args.kwonlyargs, fn.args.kw_defaults)
    ]
    return [(name, d) for name, d in out if name not in ("self", "cls")]


def _runtime_params(obj: object) -> list[tuple[str, object]]:
    sig = inspect.signature(obj)  # raises ValueError when PyO3 wrote no text signature
    return [(p.name, p.default) for p in sig.parameters.values() if p.name not in ("self", "cls")]


def _public(obj: object) -> set[str]:
    return {n for n in vars(obj) if not n.startswith("_")}


def test_the_stub_and_the_module_name_the_same_things() -> None:
    assert set(_stub()) == _public(_core) == set(_core.__all__)


@pytest.mark.parametrize("name", sorted(_public(_core)))
def test_each_name_has_the_parameters_the_stub_gives_it(name: str) -> None:
    obj, stub = getattr(_core, name), _stub()[name]
    if isinstance(obj, type):
        assert isinstance(stub, ast.ClassDef), name
        methods = _methods(stub)
        public = {m for m in methods if not m.startswith("_")}
        assert public == _public(obj), name
        assert _stub_params(methods["__new__"]) == _runtime_params(obj), name  # the constructor
        for m in public:
            assert _stub_params(methods[m]) == _runtime_params(getattr(obj, m)), f"{name}.{m}"
    else:
        assert isinstance(stub, ast.FunctionDef), name
        assert _stub_params(stub) == _runtime_params(obj), name


def test_every_parameter_and_return_of_the_stub_is_typed() -> None:
    for name, node in _stub().items():
        functions = _methods(node).values() if isinstance(node, ast.ClassDef) else [node]
        for fn in functions:
            args = fn.args.posonlyargs + fn.args.args + fn.args.kwonlyargs
            untyped = [a.arg for a in args if a.annotation is None and a.arg not in ("self", "cls")]
            assert not untyped and fn.returns is not None, (name, fn.name, untyped)


def test_the_check_is_not_vacuous() -> None:
    """A parameter renamed in the stub is caught (the comparison reads real signatures)."""
    fn = ast.parse("def greedy_tree(conds, keys, allowed, n_moves, max_leaves): ...").body[0]
    assert _stub_params(fn) != _runtime_params(_core.greedy_tree)
    assert _runtime_params(_core.Arena.explore) == [("seconds", None), ("memory", None), ("max_configs", None)]
