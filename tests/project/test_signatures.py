"""No public function or method takes more than 10 parameters: a longer list is a typed record.

Every module under ``src/targetacq`` is read with :mod:`ast` (nothing is imported). A function's
parameters are its positional-only, positional and keyword-only ones, plus ``*args`` and
``**kwargs`` (one each); a method's ``self`` or ``cls`` is not counted. Exempt:

- private names (a leading ``_``, but not a dunder: a class's ``__init__`` is its call),
  members of private classes, and functions nested in functions (none of them is an API);
- typer commands (decorated ``@<app>.command(...)``): each command-line option is a parameter
  of the command function by typer's design, and the command's interface is its command line,
  not a Python call.

Numba kernels are not exempt: nopython code takes flat arrays rather than records, so a kernel
with a long argument list is private to ``engines/`` (a leading ``_``), behind the engines'
public classes.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2] / "src" / "targetacq"
LIMIT = 10


def parameter_count(function: ast.FunctionDef | ast.AsyncFunctionDef, *, method: bool) -> int:
    """Parameters of ``function``: positional-only, positional, keyword-only, ``*args`` and
    ``**kwargs``; without a method's first parameter when it is ``self`` or ``cls``."""
    args = function.args
    named = [*args.posonlyargs, *args.args, *args.kwonlyargs]
    count = len(named) + (args.vararg is not None) + (args.kwarg is not None)
    if method and named and named[0].arg in ("self", "cls"):
        count -= 1
    return count


def _decorator_name(decorator: ast.expr) -> str:
    target = decorator.func if isinstance(decorator, ast.Call) else decorator
    if isinstance(target, ast.Attribute):
        return target.attr
    if isinstance(target, ast.Name):
        return target.id
    return ""


def _exempt(function: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    names = {_decorator_name(d) for d in function.decorator_list}
    return "command" in names


def _private(name: str) -> bool:
    """A leading underscore, but not a dunder: ``__init__`` and ``__call__`` are how a class is
    called."""
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def long_signatures(tree: ast.Module) -> Iterator[tuple[str, int, int]]:
    """``(qualified name, line, parameter count)`` of each public function or method of a
    module with more than :data:`LIMIT` parameters."""

    def walk(node: ast.AST, prefix: str, in_class: bool) -> Iterator[tuple[str, int, int]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.ClassDef):
                if not child.name.startswith("_"):
                    yield from walk(child, f"{prefix}{child.name}.", True)
            elif isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                if _private(child.name) or _exempt(child):
                    continue
                count = parameter_count(child, method=in_class)
                if count > LIMIT:
                    yield f"{prefix}{child.name}", child.lineno, count
            elif isinstance(child, ast.If | ast.Try):  # definitions under `if TYPE_CHECKING:` etc.
                yield from walk(child, prefix, in_class)

    yield from walk(tree, "", False)


def test_the_counter_counts_every_kind_of_parameter() -> None:
    source = (
        "def eleven(a, b, /, c, d=1, *args, e, f=2, g, h, i, **kwargs): pass\n"
        "def ten(a, b, c, d, e, f, g, h, i, j): pass\n"
        "def _private(a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "class Public:\n"
        "    def method(self, a, b, c, d, e, f, g, h, i, j): pass\n"
        "    def too_many(self, a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "    @classmethod\n"
        "    def build(cls, *a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "    def __init__(self, a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "    def _helper(self, a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "class _Hidden:\n"
        "    def method(self, a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "@app.command('x')\n"
        "def command(a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "@compiled\n"
        "def kernel(a, b, c, d, e, f, g, h, i, j, k): pass\n"
    )
    found = {(name, count) for name, _, count in long_signatures(ast.parse(source))}
    assert found == {
        ("eleven", 11),
        ("Public.too_many", 11),
        ("Public.build", 11),
        ("Public.__init__", 11),
        ("kernel", 11),
    }


def test_no_public_function_takes_more_than_ten_parameters() -> None:
    offenders = []
    for path in sorted(SOURCE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for name, line, count in long_signatures(tree):
            offenders.append(f"{path.relative_to(SOURCE.parent)}:{line} {name}: {count}")
    assert not offenders, (
        f"public functions with more than {LIMIT} parameters (take a typed record):\n"
        + "\n".join(offenders)
    )


# --- array parameters are annotated as arrays -----------------------------------------------

_ARRAY_TYPE = ("array_like", "array", "ndarray", "numpy.ndarray")


def documented_arrays(function: ast.FunctionDef | ast.AsyncFunctionDef) -> set[str]:
    """The parameters whose numpydoc entry gives an array type (``x : array_like, optional``)."""
    doc = ast.get_docstring(function) or ""
    lines = doc.splitlines()
    found: set[str] = set()
    section = None
    for k, line in enumerate(lines):
        text = line.strip()
        if k + 1 < len(lines) and set(lines[k + 1].strip()) == {"-"}:
            section = text
            continue
        if section != "Parameters" or " : " not in text or line.startswith((" " * 5, "\t")):
            continue
        names, kind = text.split(" : ", 1)
        if kind.split(",")[0].split(" ")[0].strip() in _ARRAY_TYPE:
            found |= {name.strip().lstrip("*") for name in names.split(",")}
    return found


def any_arrays(tree: ast.Module) -> Iterator[tuple[str, int, str]]:
    """``(function, line, parameter)`` of each parameter of a public function documented as an
    array but annotated ``Any``."""
    for node in ast.walk(tree):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        if node.name.startswith("_") and node.name != "__init__":
            continue
        arrays = documented_arrays(node)
        args = node.args
        for arg in [*args.posonlyargs, *args.args, *args.kwonlyargs]:
            annotation = ast.unparse(arg.annotation) if arg.annotation else None
            if arg.arg in arrays and annotation in ("Any", "Any | None"):
                yield node.name, node.lineno, arg.arg


def test_the_array_check_reads_the_docstring() -> None:
    source = (
        "def f(x: Any, y: Any, n: int, z: Any | None = None, w: Array = 1):\n"
        '    """F.\n\n    Parameters\n    ----------\n    x : array_like\n        X.\n'
        "    y : str\n        Y.\n    n : int\n    z, w : array_like, optional\n"
        '        Z and W.\n    """\n'
    )
    assert [p for _, _, p in any_arrays(ast.parse(source))] == ["x", "z"]


def test_array_parameters_are_annotated_as_arrays() -> None:
    """A parameter documented as ``array_like`` is annotated ``Array`` (from
    :mod:`targetacq.base.arrays`), not ``Any``: the annotation says what the docstring says."""
    found = [
        f"{path.relative_to(SOURCE)}:{line} {function}({name})"
        for path in sorted(SOURCE.rglob("*.py"))
        for function, line, name in any_arrays(ast.parse(path.read_text(encoding="utf-8")))
    ]
    assert not found, "array parameters annotated Any:\n" + "\n".join(found)
