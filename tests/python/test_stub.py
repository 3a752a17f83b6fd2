"""The package documents itself: its type stub (lava/_lava.pyi) names exactly what the
extension defines, with the same parameters, and every public function, class and method
has a docstring that help() shows."""
import ast
import inspect
import os
import re

import lava
from lava import _lava

STUB = os.path.join(os.path.dirname(lava.__file__), "_lava.pyi")


def stub_tree():
    return ast.parse(open(STUB).read())


def parameters(node):
    """A stub function's parameter names, without self."""
    a = node.args
    names = [p.arg for p in a.posonlyargs + a.args + a.kwonlyargs]
    if a.kwarg:
        names.append("**")
    return [n for n in names if n != "self"]


def runtime_parameters(function):
    """The parameter names of pybind11's signature line ('name(a: int, b: str = ...) -> x')."""
    first = (function.__doc__ or "").splitlines()[0]
    inside = re.match(r"\w+\((.*)\)", first)
    assert inside, "no signature in the docstring of %s" % function
    parts, depth, current = [], 0, ""
    for c in inside.group(1):  # split at the commas outside brackets: (1280, 720) is one
        depth += c in "([{"
        depth -= c in ")]}"
        if c == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += c
    parts.append(current)
    names = []
    for part in parts:
        part = part.strip()
        if not part:
            continue
        if part.startswith("**"):
            names.append("**")
        else:
            names.append(part.split(":")[0].strip())
    return [n for n in names if n != "self"]


def test_the_stub_names_exactly_the_modules_functions_and_classes():
    tree = stub_tree()
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    stubbed |= {t.id for n in tree.body if isinstance(n, ast.AnnAssign) for t in [n.target]}
    public = {n for n in dir(_lava) if not n.startswith("_") or n == "__version__"}
    assert stubbed - {"SceneLike", "PathLike"} == public  # the stub's own aliases
    assert set(lava.__all__) == public | {"presets"}  # presets(): the package's own, in Python


def test_functions_and_methods_have_the_stubs_parameters_and_docstrings():
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef):
            function = getattr(_lava, node.name)
            assert parameters(node) == runtime_parameters(function), node.name
            assert len(function.__doc__.splitlines()) > 1, "%s has no docstring" % node.name
        elif isinstance(node, ast.ClassDef):
            cls = getattr(_lava, node.name)
            assert cls.__doc__, "%s has no docstring" % node.name
            for member in node.body:
                if not isinstance(member, ast.FunctionDef):
                    continue
                decorators = {getattr(d, "id", None) for d in member.decorator_list}
                attribute = inspect.getattr_static(cls, member.name)
                if "property" in decorators:
                    assert isinstance(attribute, property), member.name
                    assert attribute.__doc__, "%s.%s has no docstring" % (node.name, member.name)
                    continue
                method = getattr(cls, member.name)
                if issubclass(cls, Exception):
                    continue
                if member.name == "__init__":
                    assert runtime_parameters(method) == parameters(member), node.name
                    continue
                assert parameters(member) == runtime_parameters(method), \
                    "%s.%s" % (node.name, member.name)
                assert len(method.__doc__.splitlines()) > 1, \
                    "%s.%s has no docstring" % (node.name, member.name)


def test_help_shows_the_simulations_documented_methods():
    text = inspect.getdoc(lava.Simulation) + "".join(
        inspect.getdoc(getattr(lava.Simulation, m)) or "" for m in
        ("advance", "state", "set_state", "checkpoint", "resume"))
    for word in ("advance", "checkpoint", "Ctrl-C", "bit for bit"):
        assert word in text
    import pydoc
    rendered = pydoc.render_doc(lava.Simulation, renderer=pydoc.plaintext)
    for method in ("advance", "state", "set_state", "checkpoint", "resume", "particles"):
        assert method in rendered


def test_the_package_is_typed():
    assert os.path.exists(os.path.join(os.path.dirname(lava.__file__), "py.typed"))
