"""The package's import rules, checked on its source (the contributor page "Architecture").

Every module under ``src/targetacq`` is parsed with :mod:`ast`, nothing is imported, and every
import statement is collected at any depth: at module level, inside functions and methods
(lazy imports for a fast start are welcome, but they count like any other import, so a
function-level import cannot hide an upward one) and inside ``if TYPE_CHECKING:`` blocks.

How an import becomes an edge of the module graph:

* relative imports are resolved against the importing module's package;
* ``import a.b.c`` is an edge to ``a.b.c`` only. Python also runs ``a/__init__`` and
  ``a/b/__init__`` first, but a package ``__init__`` that re-exports its submodules (as
  ``targetacq/__init__.py`` does) would otherwise put every module on a cycle with the package;
* ``from pkg import name`` is an edge to the submodule ``pkg.name`` when that is a module, and
  otherwise to ``pkg`` itself. So ``from targetacq import atmosphere`` depends on
  :mod:`targetacq.physics.atmosphere`, while ``from targetacq import dri_ranges`` depends on the
  package ``targetacq`` (and so on whatever the package imports); inside the package, import a name
  from the module that defines it.

Modules imported by a name computed at run time (``importlib.import_module``) are no edge: the
CLI finds its command modules that way, by name in its command table, as plugins (each command
module imports the CLI package to register on its ``app``, never the other way round).

Imports under ``if TYPE_CHECKING:`` never run, so they cannot make an import cycle, and they are
left out of the cycle rule (a type annotation may name a record of a higher layer without the
module depending on it at run time). They count for every other rule.

The rules:

1. **Layers**: the package's folders are its layers (:data:`LAYERS`: ``base``, ``io``,
   ``acquisition``, ``physics``, ``sensors``, ``scenario``, ``core``, ``run``, ``reports``, then
   the front-ends); every module sits in one of them (no top-level module but the package's
   ``__init__`` and ``__main__``), and imports only modules of its own layer or of layers before
   it (imports under ``if TYPE_CHECKING:`` aside, as for cycles). A new folder must be placed in
   a layer here (and on the contributor page "Architecture").
2. **No cycle** in the module graph (module- and function-level imports together).
3. **The CLI is a leaf**: nothing outside ``targetacq/cli/`` imports :mod:`targetacq.cli` or
   anything under it. ``targetacq/__main__.py`` (``python -m targetacq``) is the CLI's second
   entry point and belongs to the CLI.
4. **Front-ends are independent**: the front-ends are :mod:`targetacq.cli`,
   :mod:`targetacq.web`, :mod:`targetacq.envs` and :mod:`targetacq.validation`; none imports
   another. What two front-ends share belongs in a lower layer. The one exception is starting
   another front-end: the CLI is the package's command, and two of its commands exist only to
   start another front-end (``targetacq serve`` the web explorer, ``targetacq validation`` the
   validation page). Those two command modules (:data:`LAUNCHERS`) may import the public names
   of the front-end they start, and nothing else of any front-end.
5. **No reaching into another module's internals.** A leading underscore makes a thing private
   to the namespace that holds it:

   * a private *name* (``_ratio_anchors``; dunders such as ``__version__`` are not private) is
     private to its module; the modules of a component (:data:`SHARED_UNITS`: the core, its
     engines, the sensor types, each front-end) form one unit: any module of
     ``targetacq.core.engines`` may import ``targetacq.core.engines.numba_kernels._x``, but no
     module may import ``targetacq.acquisition.path_noise._x`` except that module itself;
   * a private *module* (``_simd``) is private to the package that holds it:
     ``targetacq.core.engines._simd`` is for ``targetacq.core.engines`` and
     ``targetacq.validation._page`` for ``targetacq.validation``.

   Both ``from m import _x`` and an attribute ``m._x`` on an imported module ``m`` count.
"""

from __future__ import annotations

import ast
import textwrap
from dataclasses import dataclass
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGE = "targetacq"
CLI = "targetacq.cli"
FRONT_ENDS = (
    "targetacq.cli",
    "targetacq.web",
    "targetacq.envs",
    "targetacq.tracking",
    "targetacq.validation",
)
CLI_ENTRY_POINTS = ("targetacq.__main__",)
LAYERS: tuple[tuple[str, tuple[str, ...]], ...] = (
    # the package itself: re-exports (on first use) and __version__ only
    ("base", ("targetacq", "targetacq.base")),
    ("io", ("targetacq.io",)),
    ("acquisition", ("targetacq.acquisition",)),
    ("physics", ("targetacq.physics",)),
    ("sensors", ("targetacq.sensors",)),
    ("scenario", ("targetacq.scenario",)),
    ("core", ("targetacq.core",)),
    ("run", ("targetacq.run",)),
    ("reports", ("targetacq.reports",)),
    (
        "front-ends",
        (
            "targetacq.__main__",
            "targetacq.cli",
            "targetacq.envs",
            "targetacq.examples",  # scripts shipped with the examples, run by users
            "targetacq.tracking",
            "targetacq.validation",
            "targetacq.web",
        ),
    ),
)
"""The layers, lowest first: (name, the top-level modules and subpackages in it)."""

LAUNCHERS = {
    "targetacq.cli.serve": "targetacq.web",
    "targetacq.cli.validation": "targetacq.validation",
}
"""CLI command modules that start another front-end → the front-end each may import."""


@dataclass(frozen=True)
class Import:
    """One import of a module of the package (or of one name from it)."""

    importer: str  # the importing module, dotted
    target: str  # the imported module (the submodule when ``from pkg import submodule``)
    name: str | None  # the name taken from ``target`` (``from target import name``), else None
    line: int
    type_checking: bool  # inside ``if TYPE_CHECKING:``

    def __str__(self) -> str:
        imported = self.target + (f".{self.name}" if self.name else "")
        return f"{self.importer} (line {self.line}) imports {imported}"


def module_names(src: Path, package: str) -> dict[str, Path]:
    """Every module of ``package`` under ``src``: dotted name → file."""
    modules = {}
    for path in sorted((src / package).rglob("*.py")):
        parts = list(path.relative_to(src).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        modules[".".join(parts)] = path
    return modules


def _is_package(modules: dict[str, Path], module: str) -> bool:
    return modules[module].name == "__init__.py"


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imports_of(module: str, path: Path, modules: dict[str, Path], package: str) -> list[Import]:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    base = module if _is_package(modules, module) else module.rpartition(".")[0]
    found: list[Import] = []
    aliases: dict[str, str] = {}  # a local name bound to a module of the package → that module

    def inside(target: str) -> bool:
        return target == package or target.startswith(package + ".")

    def visit(node: ast.AST, type_checking: bool) -> None:
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            for child in node.body:
                visit(child, True)
            for child in node.orelse:
                visit(child, type_checking)
            return
        if isinstance(node, ast.Import):
            for alias in node.names:
                if inside(alias.name):
                    found.append(Import(module, alias.name, None, node.lineno, type_checking))
                    if alias.asname:
                        aliases[alias.asname] = alias.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = base.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                source = ".".join(anchor + ([node.module] if node.module else []))
            else:
                source = node.module or ""
            if inside(source):
                for alias in node.names:
                    submodule = f"{source}.{alias.name}"
                    if submodule in modules:
                        found.append(Import(module, submodule, None, node.lineno, type_checking))
                        aliases[alias.asname or alias.name] = submodule
                    else:
                        found.append(Import(module, source, alias.name, node.lineno, type_checking))
        for child in ast.iter_child_nodes(node):
            visit(child, type_checking)

    visit(tree, False)
    # Attributes of imported modules: ``noise._ratio_anchors`` reads a name like an import does.
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in aliases
            and _is_private(node.attr)
        ):
            found.append(Import(module, aliases[node.value.id], node.attr, node.lineno, False))
    return found


def import_graph(src: Path, package: str) -> tuple[dict[str, Path], list[Import]]:
    """The package's modules and every import between them, at any depth."""
    modules = module_names(src, package)
    imports = [imp for m, p in modules.items() for imp in _imports_of(m, p, modules, package)]
    return modules, imports


def _is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _within(module: str, namespace: str) -> bool:
    return module == namespace or module.startswith(namespace + ".")


SHARED_UNITS = (
    "targetacq.core.engines",
    "targetacq.core",
    "targetacq.sensors",
    "targetacq.cli",
    "targetacq.envs",
    "targetacq.examples",
    "targetacq.validation",
    "targetacq.web",
)
"""Subpackages whose modules share their private names (one component each, the first that
holds a module, so the engines are a unit apart from the rest of the core). The modules of a
layer's folder (``targetacq.physics.atmosphere``, ``targetacq.run.simulation``) are each a unit
of their own."""


def _unit(module: str, package: str, shared: tuple[str, ...] = SHARED_UNITS) -> str:
    """The unit that shares a module's private names: its component (:data:`SHARED_UNITS`,
    or in a test's fixture package its top-level subpackage), or the module itself."""
    if package != PACKAGE:
        parts = module.split(".")
        return ".".join(parts[: len(package.split(".")) + 1])
    return next((unit for unit in shared if _within(module, unit)), module)


def cycles(modules: dict[str, Path], imports: list[Import]) -> list[list[str]]:
    """The strongly connected components of more than one module (or with a self-import), each
    as one cycle through it (Tarjan's algorithm, then a shortest path back to the start)."""
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for imp in imports:
        if not imp.type_checking and imp.target in graph:
            graph[imp.importer].add(imp.target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def strongconnect(v: str) -> None:  # recursion depth ≤ number of modules
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                strongconnect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1 or v in graph[v]:
                components.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            strongconnect(v)

    found = []
    for component in components:
        start, members = component[0], set(component)
        previous: dict[str, str] = {}
        frontier, seen = [start], {start}
        while frontier and start not in previous:
            following = []
            for v in frontier:
                for w in sorted(graph[v] & members):
                    if w == start and start not in previous:
                        previous[start] = v
                    elif w not in seen:
                        seen.add(w)
                        previous[w] = v
                        following.append(w)
            frontier = following
        path, v = [start], previous[start]
        while v != start:
            path.append(v)
            v = previous[v]
        found.append([start, *reversed(path[1:]), start])
    return found


def layer_of(module: str, layers: tuple[tuple[str, tuple[str, ...]], ...] = LAYERS) -> int:
    """The index in ``layers`` of the layer that holds ``module`` (-1: none)."""
    for index, (_, members) in enumerate(layers):
        if any(_within(module, member) for member in members if member.count(".")) or (
            module in members
        ):
            return index
    return -1


def upward_imports(
    modules: dict[str, Path],
    imports: list[Import],
    layers: tuple[tuple[str, tuple[str, ...]], ...] = LAYERS,
) -> tuple[list[str], list[Import]]:
    """The modules in no layer, and the imports of a later layer (TYPE_CHECKING ones aside)."""
    unplaced = sorted(m for m in modules if layer_of(m, layers) < 0)
    upward = [
        imp
        for imp in imports
        if not imp.type_checking
        and imp.target in modules
        and 0 <= layer_of(imp.importer, layers) < layer_of(imp.target, layers)
    ]
    return unplaced, upward


def cli_imports(imports: list[Import], cli: str = CLI) -> list[Import]:
    """Imports of the CLI (or anything under it) from outside it."""
    return [
        imp
        for imp in imports
        if _within(imp.target, cli)
        and not _within(imp.importer, cli)
        and imp.importer not in CLI_ENTRY_POINTS
    ]


def front_end_imports(
    imports: list[Import],
    front_ends: tuple[str, ...] = FRONT_ENDS,
    launchers: dict[str, str] = LAUNCHERS,
) -> list[Import]:
    """Imports of one front-end by another (but a launcher's of the public names of the
    front-end it starts)."""

    def launches(imp: Import) -> bool:
        started = launchers.get(imp.importer)
        return (
            started is not None
            and _within(imp.target, started)
            and not any(_is_private(part) for part in imp.target.split("."))
            and not (imp.name is not None and _is_private(imp.name))
        )

    def front_end(module: str) -> str | None:
        if module in CLI_ENTRY_POINTS:
            return CLI
        return next((f for f in front_ends if _within(module, f)), None)

    return [
        imp
        for imp in imports
        if front_end(imp.target) not in (None, front_end(imp.importer))
        and front_end(imp.importer) is not None
        and not launches(imp)
    ]


def private_imports(imports: list[Import], package: str = PACKAGE) -> list[Import]:
    """Imports of a private name or a private module from outside the namespace it is private to."""
    found = []
    for imp in imports:
        parts = imp.target.split(".")
        for i, part in enumerate(parts):
            if _is_private(part) and not _within(imp.importer, ".".join(parts[:i])):
                found.append(imp)
                break
        else:
            if (
                imp.name is not None
                and _is_private(imp.name)
                and _unit(imp.importer, package) != _unit(imp.target, package)
            ):
                found.append(imp)
    return found


@pytest.fixture(scope="module")
def graph() -> tuple[dict[str, Path], list[Import]]:
    return import_graph(SRC, PACKAGE)


def _report(found: list[Import]) -> str:
    return "\n".join(map(str, found))


def test_the_graph_sees_the_package(graph: tuple[dict[str, Path], list[Import]]) -> None:
    """A sanity floor: the walk finds the modules and imports it must, at every depth."""
    modules, imports = graph
    assert {
        "targetacq",
        "targetacq.core.evaluation",
        "targetacq.core.engines.numba_kernels",
    } <= set(modules)
    assert len(modules) > 80
    edges = {(imp.importer, imp.target, imp.type_checking) for imp in imports}
    # at module level; inside a function (core.active imports the radar equation on use);
    # under TYPE_CHECKING
    assert ("targetacq.run.model_chain", "targetacq.core.evaluation", False) in edges
    assert ("targetacq.core.active", "targetacq.physics.radar_equation", False) in edges
    assert ("targetacq.run.false_targets", "targetacq.core.records", True) in edges


def test_every_module_imports_only_its_layer_and_those_before(
    graph: tuple[dict[str, Path], list[Import]],
) -> None:
    modules, imports = graph
    unplaced, upward = upward_imports(modules, imports)
    assert not unplaced, "modules in no layer of LAYERS (place them):\n" + "\n".join(unplaced)
    names = [name for name, _ in LAYERS]
    assert not upward, "imports of a later layer:\n" + "\n".join(
        f"{imp} ({names[layer_of(imp.importer)]} → {names[layer_of(imp.target)]})" for imp in upward
    )


def test_no_import_cycle(graph: tuple[dict[str, Path], list[Import]]) -> None:
    modules, imports = graph
    found = cycles(modules, imports)
    assert not found, "import cycles:\n" + "\n".join(" → ".join(c) for c in found)


def test_nothing_outside_the_cli_imports_it(graph: tuple[dict[str, Path], list[Import]]) -> None:
    _, imports = graph
    found = cli_imports(imports)
    assert not found, "imports of targetacq.cli from outside it:\n" + _report(found)


def test_no_front_end_imports_another(graph: tuple[dict[str, Path], list[Import]]) -> None:
    _, imports = graph
    found = front_end_imports(imports)
    assert not found, "a front-end imports another:\n" + _report(found)


def test_no_private_imports(graph: tuple[dict[str, Path], list[Import]]) -> None:
    _, imports = graph
    found = private_imports(imports)
    assert not found, "imports of another module's private names:\n" + _report(found)


# The checker itself, on a small package written for it.


def _write(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text), encoding="utf-8")


@pytest.fixture
def fixture_package(tmp_path: Path) -> Path:
    _write(
        tmp_path,
        {
            # the top-level package re-exports a function and a module: no cycle by itself
            "pkg/__init__.py": """
                from pkg.low import helper
                from pkg import mid
                """,
            "pkg/_shared.py": "def tool(): ...\n_hidden = 1\n",
            "pkg/low.py": """
                from pkg._shared import tool
                def helper(): ...
                _secret = 2
                """,
            # mid ↔ high, the upward half hidden in a function
            "pkg/mid.py": """
                from . import low
                def f():
                    from pkg.high import g
                    return low._secret
                """,
            "pkg/high.py": """
                from typing import TYPE_CHECKING
                from pkg.mid import f
                from pkg._shared import _hidden
                if TYPE_CHECKING:
                    from pkg.top import T
                """,
            # a type-checking-only import upwards (top → high is real): no cycle
            "pkg/top.py": "import pkg.high as h\nT = int\n",
            # importing a function through the package that re-exports it: a real cycle
            "pkg/user.py": "from pkg import helper\n",
            "pkg/sub/__init__.py": "",
            "pkg/sub/a.py": "from pkg.sub.b import _inner\nfrom pkg.sub import _impl\n",
            "pkg/sub/b.py": "_inner = 1\n",
            "pkg/sub/_impl.py": "x = 1\n",
            "pkg/front/__init__.py": "from pkg.sub._impl import x\nfrom pkg import cli\n",
            "pkg/cli/__init__.py": "from pkg import front\n",
            "pkg/cli/run.py": "from .. import front\n",
            # a launcher: may import the public names of the front-end it starts, only
            "pkg/cli/start.py": "from pkg.front import run, _setting\n",
        },
    )
    return tmp_path


def test_the_checker_finds_what_is_wrong(fixture_package: Path) -> None:
    modules, imports = import_graph(fixture_package, "pkg")
    assert set(modules) == {
        "pkg",
        "pkg._shared",
        "pkg.low",
        "pkg.mid",
        "pkg.high",
        "pkg.top",
        "pkg.user",
        "pkg.sub",
        "pkg.sub.a",
        "pkg.sub.b",
        "pkg.sub._impl",
        "pkg.front",
        "pkg.cli",
        "pkg.cli.run",
        "pkg.cli.start",
    }
    found = {frozenset(c) for c in cycles(modules, imports)}
    # Cycles: mid → high (inside a function) → mid, and front ↔ cli. None through user → pkg
    # (the package re-exports `helper`, but imports no user back), nor through top → high,
    # whose import of top runs only under TYPE_CHECKING.
    assert found == {
        frozenset({"pkg.mid", "pkg.high"}),
        frozenset({"pkg.front", "pkg.cli"}),
    }
    for c in cycles(modules, imports):
        assert c[0] == c[-1] and len(c) == 3
    assert {(i.importer, i.target) for i in cli_imports(imports, "pkg.cli")} == {
        ("pkg.front", "pkg.cli")
    }
    crossing = front_end_imports(imports, ("pkg.cli", "pkg.front"), {"pkg.cli.start": "pkg.front"})
    assert {(i.importer, i.target, i.name) for i in crossing} == {
        ("pkg.front", "pkg.cli", None),
        ("pkg.cli", "pkg.front", None),
        ("pkg.cli.run", "pkg.front", None),
        ("pkg.cli.start", "pkg.front", "_setting"),
    }
    layers = (
        ("low", ("pkg", "pkg._shared", "pkg.low", "pkg.sub")),
        ("mid", ("pkg.mid", "pkg.top")),  # pkg.user in no layer
        ("high", ("pkg.high", "pkg.front", "pkg.cli")),
    )
    unplaced, upward = upward_imports(modules, imports, layers)
    assert unplaced == ["pkg.user"]
    # the package's import of a submodule counts; high → top under TYPE_CHECKING does not
    assert {(i.importer, i.target) for i in upward} == {
        ("pkg", "pkg.mid"),
        ("pkg.mid", "pkg.high"),
        ("pkg.top", "pkg.high"),
    }
    private = {(i.importer, i.target, i.name) for i in private_imports(imports, "pkg")}
    assert private == {
        ("pkg.mid", "pkg.low", "_secret"),  # an attribute of an imported module
        ("pkg.high", "pkg._shared", "_hidden"),  # a private name of a shared private module
        ("pkg.front", "pkg.sub._impl", "x"),  # another subpackage's private module
        ("pkg.cli.start", "pkg.front", "_setting"),
    }


def test_a_re_exported_name_imported_back_is_a_cycle(tmp_path: Path) -> None:
    _write(
        tmp_path,
        {
            "pkg/__init__.py": "from pkg.low import helper\nfrom pkg.user import use\n",
            "pkg/low.py": "def helper(): ...\n",
            "pkg/user.py": "from pkg import helper\ndef use(): ...\n",
        },
    )
    modules, imports = import_graph(tmp_path, "pkg")
    assert cycles(modules, imports) == [["pkg", "pkg.user", "pkg"]]
    # the same import of the defining module is no cycle
    (tmp_path / "pkg/user.py").write_text("from pkg.low import helper\ndef use(): ...\n")
    modules, imports = import_graph(tmp_path, "pkg")
    assert cycles(modules, imports) == []
