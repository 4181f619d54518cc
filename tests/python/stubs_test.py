"""The type stubs (semfuse/_semfuse.pyi) describe the native module as it is, and what an editor
shows is documented: every name, method and parameter of the module is in the stubs and the other
way round, every method has a docstring, and the package exports all of it."""
from __future__ import annotations

import ast
import importlib.util
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import semfuse
from semfuse import _semfuse

STUB = Path(_semfuse.__file__).with_name("_semfuse.pyi")
SOURCE_DIR = Path(os.environ.get("SEMFUSE_SOURCE_DIR", Path(__file__).resolve().parents[2]))
KEPT_DUNDERS = {"__init__", "__enter__", "__exit__", "__iter__", "__next__", "__contains__", "__len__", "__eq__"}


def stub_tree() -> ast.Module:
    return ast.parse(STUB.read_text())


def is_typing_helper(node: ast.stmt) -> bool:
    """A name the stubs define for their own annotations: an alias or a TypedDict."""
    if isinstance(node, ast.Assign):
        return True
    return isinstance(node, ast.ClassDef) and any(getattr(b, "id", "") == "TypedDict" for b in node.bases)


def stub_names() -> dict[str, ast.stmt]:
    names = {}
    for node in stub_tree().body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = node
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                names[target.id] = node
    return names


def module_names() -> set[str]:
    return {n for n in dir(_semfuse) if not n.startswith("__") or n == "__version__"}


def class_members(cls: type) -> set[str]:
    """Public members, the dunders a user calls, and __init__ when the class can be constructed
    (pybind11 gives the others a generic __init__ that refuses)."""
    members = {n for n in vars(cls) if not n.startswith("_") or n in KEPT_DUNDERS}
    if not (cls.__init__.__doc__ or "").startswith("__init__("):
        members.discard("__init__")
    return members


def stub_members(node: ast.ClassDef) -> set[str]:
    members = set()
    for item in node.body:
        if isinstance(item, ast.FunctionDef):
            members.add(item.name)
        elif isinstance(item, ast.AnnAssign):
            members.add(item.target.id)
    return members


def test_the_stubs_name_every_name_of_the_module_and_no_other() -> None:
    stubs = stub_names()
    module = module_names()
    assert module - set(stubs) == set(), "in the module, missing from the stubs"
    extra = {n for n, node in stubs.items() if n not in module and not is_typing_helper(node)}
    assert extra == set(), "in the stubs, not in the module"


@pytest.mark.parametrize("name", sorted(n for n in dir(_semfuse) if isinstance(getattr(_semfuse, n), type)))
def test_the_stubs_of_a_class_name_its_members_and_their_parameters(name: str) -> None:
    cls = getattr(_semfuse, name)
    node = stub_names()[name]
    assert isinstance(node, ast.ClassDef)
    assert stub_members(node) == class_members(cls)
    for item in node.body:
        if not isinstance(item, ast.FunctionDef) or isinstance(vars(cls)[item.name], property):
            continue
        if item.args.vararg is not None:
            continue  # __exit__(*args)
        if item.name.startswith("__") and item.name != "__init__":
            continue  # operators: their parameter names are pybind11's (arg0)
        signature = getattr(cls, item.name).__doc__.splitlines()[0]
        params = signature[signature.index("(") + 1:signature.rindex(") ->")]
        native = [re.match(r"(\w+)(?::[^=]*)?(?: = (.*))?$", p).groups() for p in re.split(r", (?=\w+: )", params)]
        args = item.args.args
        defaults = [None] * (len(args) - len(item.args.defaults)) + list(item.args.defaults)
        stubbed = [(a.arg, None if d is None else ast.unparse(d)) for a, d in zip(args, defaults)]
        assert [n for n, _ in stubbed] == [n for n, _ in native], f"{name}.{item.name}: parameters"
        for (arg, stub_default), (_, native_default) in zip(stubbed, native):
            if native_default is None or stub_default is None:
                assert native_default == stub_default, f"{name}.{item.name}({arg}): default"
            else:
                assert ast.literal_eval(stub_default) == ast.literal_eval(native_default), f"{name}.{item.name}({arg})"


def test_every_function_and_method_is_documented() -> None:
    undocumented = []
    for name in dir(_semfuse):
        value = getattr(_semfuse, name)
        if isinstance(value, type):
            if not (value.__doc__ or "").strip():
                undocumented.append(name)
            for member, routine in vars(value).items():
                if member.startswith("_") or isinstance(routine, property) or not callable(routine):
                    continue
                lines = (routine.__doc__ or "").strip().splitlines()
                if len(lines) < 2:  # pybind11 puts the signature first, the docstring after it
                    undocumented.append(f"{name}.{member}")
        elif callable(value) and len((value.__doc__ or "").strip().splitlines()) < 2:
            undocumented.append(name)
    assert undocumented == []


def test_the_package_exports_the_module_and_its_exceptions() -> None:
    exported = set(semfuse.__all__)
    assert exported == (module_names() - {"_stop_all_threads"}) | {"Error", "ServerError", "ClientError",
                                                                    "CallTimeout"}
    for name in exported:
        assert hasattr(semfuse, name), name
    assert issubclass(semfuse.CallTimeout, TimeoutError) and issubclass(semfuse.CallTimeout, semfuse.Error)
    assert issubclass(semfuse.ServerError, semfuse.Error) and not issubclass(semfuse.ServerError, TimeoutError)
    assert (Path(semfuse.__file__).parent / "py.typed").exists()
    assert inspect.getdoc(semfuse).startswith("semfuse from Python")


def test_mypy_reads_the_stubs_and_checks_the_examples_against_them() -> None:
    """The stubs are valid for type checkers (every name in an annotation exists), and the examples
    and the benchmark use the API as the stubs describe it."""
    if importlib.util.find_spec("mypy") is None:
        if os.environ.get("CI"):
            pytest.fail("python3-mypy is missing (deploy/install-deps.sh)")
        pytest.skip("python3-mypy is not installed")
    examples = sorted(str(p) for folder in ("examples", "bench")
                      for p in (SOURCE_DIR / "client/python" / folder).glob("*.py"))
    assert examples
    done = subprocess.run([sys.executable, "-m", "mypy", "--ignore-missing-imports", "--no-incremental",
                           "--cache-dir", os.devnull, str(STUB), *examples],
                          capture_output=True, text=True, timeout=600, env={**os.environ, "MYPYPATH": str(STUB.parents[1])})
    assert done.returncode == 0, done.stdout + done.stderr
