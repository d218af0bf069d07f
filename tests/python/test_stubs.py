"""The type stubs (.pyi) name every class, function, method and argument of the module,
with the module's defaults, so that editors complete what exists."""

import ast
import inspect
import pathlib

import pytest

import hairscatter
from hairscatter import _core

STUBS = pathlib.Path(hairscatter.__file__).with_name("_core.pyi")


def split_top_level(text):
    parts, depth, start = [], 0, 0
    for i, c in enumerate(text):
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:].strip())
    return parts


def runtime_signature(obj):
    """[(name, default or None)] from pybind11's docstring signature (self excluded)."""
    first = obj.__doc__.splitlines()[0]
    inner = first[first.index("(") + 1 : first.rindex(")")]
    out = []
    for part in split_top_level(inner):
        name = part.split(":")[0].split("=")[0].strip()
        default = part.split(" = ", 1)[1] if " = " in part else None
        if name != "self":
            out.append((name, default))
    return out


def stub_signature(node):
    a = node.args
    names = [x.arg for x in a.posonlyargs + a.args]
    defaults = [None] * (len(names) - len(a.defaults)) + [ast.unparse(d) for d in a.defaults]
    out = [(n, d) for n, d in zip(names, defaults) if n != "self"]
    if a.kwonlyargs:
        out.append(("*", None))
        out += [(x.arg, None if d is None else ast.unparse(d)) for x, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.kwarg:
        out.append(("**" + a.kwarg.arg, None))
    return out


def same_default(runtime, stub):
    if stub is None or stub == "...":
        return True
    try:
        return ast.literal_eval(runtime) == ast.literal_eval(stub)
    except (ValueError, SyntaxError):
        return runtime.strip("'\"") == stub.strip("'\"")


def stub_tree():
    return ast.parse(STUBS.read_text())


def public(names):
    return {n for n in names if not n.startswith("_")}


def test_the_stubs_name_every_public_object():
    tree = stub_tree()
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    assert public(dir(_core)) == public(stubbed)


def function_cases():
    tree = stub_tree()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            yield node.name, getattr(_core, node.name), node
        elif isinstance(node, ast.ClassDef):
            cls = getattr(_core, node.name)
            members = {m.name: m for m in node.body if isinstance(m, ast.FunctionDef)}
            runtime = {n for n, v in vars(cls).items() if not n.startswith("_") or n == "__init__"}
            declared = {n for n in members if not n.startswith("_") or n == "__init__"}
            assert runtime - {"__init__"} <= declared, f"{node.name}: {runtime - declared} not in the stubs"
            for name, m in members.items():
                attr = vars(cls).get(name)
                if attr is None or isinstance(attr, property):
                    continue
                yield f"{node.name}.{name}", getattr(cls, name), m


@pytest.mark.parametrize("qualname,obj,node", list(function_cases()), ids=lambda x: x if isinstance(x, str) else "")
def test_stub_arguments_and_defaults_match_the_module(qualname, obj, node):
    runtime, stub = runtime_signature(obj), stub_signature(node)
    assert [n for n, _ in runtime] == [n for n, _ in stub], qualname
    for (name, r), (_, s) in zip(runtime, stub):
        assert r is None or same_default(r, s), f"{qualname}({name}): module default {r}, stub {s}"


def test_every_public_callable_has_a_docstring():
    for name in public(dir(_core)):
        obj = getattr(_core, name)
        if inspect.isclass(obj):
            assert obj.__doc__, name
        elif callable(obj):
            assert len(obj.__doc__.splitlines()) > 2, f"{name} has no description"
