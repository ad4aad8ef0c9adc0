"""A Hypothesis fuzzer over the bundled scenario files.

Each example takes one of ``src/targetacq/examples/*.toml``, applies a few random mutations
(delete a key; replace a value with a random value of a random type: numbers, huge numbers,
negative numbers, "nan", strings with random units, booleans, datetimes, lists, nested tables;
add an unknown key; duplicate an entry; change the number or the unit of a quantity; shorten or
shift the time grid), writes the result to a file and runs it three ways:

- ``targetacq validate FILE`` through the command's entry point: exit status 0, or 2 with one or
  more lines on stderr, each ``targetacq: error: ...``; never a traceback;
- :func:`targetacq.scenario.schema.load_scenario`: a scenario, or a ``ScenarioError`` (a
  ``ValueError``) with a one-line message; no other exception type (no ``KeyError``,
  ``IndexError``, ``AttributeError``, ``ZeroDivisionError``, ``AssertionError``,
  ``RecursionError``, ``MemoryError``, ``FloatingPointError``, ``OverflowError``, nor a pydantic
  ``ValidationError``);
- ``ModelChain(scenario).evaluate(times)`` on at most three of the scenario's times (so that an
  example stays fast): a ``ValueError``/``TypeError`` with a one-line message, or results whose
  probabilities are all in [0, 1] and none NaN (every input is finite).

And they agree: whatever ``validate`` accepts, ``load_scenario`` loads and the evaluation runs.

Bounded for CI (``derandomize=True``, no example database); ``TARGETACQ_FUZZ_EXAMPLES=5000``
runs longer. Warnings are errors under ``pytest -W error``: a numpy ``RuntimeWarning`` on input
that is accepted fails the example.
"""

from __future__ import annotations

import contextlib
import copy
import datetime
import io
import os
import re
import tempfile
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from toml_text import toml_dumps

EXAMPLES = Path(__file__).parents[2] / "src" / "targetacq" / "examples"
BASES = {
    p.name: tomllib.loads(p.read_text(encoding="utf-8")) for p in sorted(EXAMPLES.glob("*.toml"))
}
PREFIX = "targetacq: error:"
EXAMPLES_COUNT = int(os.environ.get("TARGETACQ_FUZZ_EXAMPLES", "120"))
TASKS = ("detection", "recognition", "identification")
ALLOWED = (ValueError, TypeError)
NOT_ALLOWED_NAMES = ("ValidationError",)

# -- TOML out -------------------------------------------------------------------------------


# -- values ---------------------------------------------------------------------------------

UNITS = [
    "m", "km", "um", "mm", "nm", "s", "ns", "ms", "min", "h", "K", "mK", "degC", "degF", "deg",
    "rad", "mrad", "/km", "/m", "dB/km", "W/m^2", "kg", "", "parsec", "%", "m/s", "Hz",
]  # fmt: skip
KEYS = [
    "name", "type", "band", "pixels", "pitch", "focal_length", "hfov", "ifov", "aperture",
    "position", "waypoints", "look_at", "azimuth", "depression", "dimensions", "heading",
    "temperature", "emissivity", "material", "reflectance", "moving", "hot_spot", "clutter",
    "scr", "clutter_std", "extinction", "obscurant", "visibility", "criterion", "n50",
    "transform", "time", "start", "stop", "step", "bogus",
]  # fmt: skip
SPECIAL_STRINGS = [
    "nan", "inf", "-inf", "yes", "no", "", " ", "1e400", "nan m", "inf K", "1e400 m", "-0 m",
    "1e-400 m", "0x10 m", "1_000 m", "1,5 m", "lwir", "mwir", "visible", "8-12 um", "12-8 um",
    "haze", "haze:high", "fog:extreme", "johnson", "en62676-4", "c2nveo", "schmieder-weathersby",
    "low", "medium", "high", "thermal", "tv", "olive-paint", "vegetation", "ttpf", "nested",
    "conditional", "always", "0 0 1.5 km", "1 2 km", "\ufeff17 um", "17\u00a0um",
]  # fmt: skip

numbers = st.one_of(
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e4, max_value=1e4),
    st.sampled_from([0, -1, 1, 0.5, 1e-300, 1e300, 1e308, 2**63, 2**64, -(2**63) - 1, 5e-324]),
)
number_text = st.one_of(
    numbers.map(str),
    st.sampled_from(["1e400", "-1e400", "nan", "inf", "1e-400", "0", "-0", "1e20", "3"]),
)
quantities = st.builds(lambda n, u: f"{n} {u}".strip(), number_text, st.sampled_from(UNITS))
texts = st.one_of(
    st.sampled_from(SPECIAL_STRINGS),
    st.text(alphabet=st.characters(exclude_categories=("Cs",)), max_size=12),
)
dates = st.one_of(
    st.datetimes(min_value=datetime.datetime(1900, 1, 1), max_value=datetime.datetime(2100, 1, 1)),
    st.dates(min_value=datetime.date(1900, 1, 1), max_value=datetime.date(2100, 1, 1)),
)
leaves = st.one_of(numbers, quantities, texts, st.booleans(), dates)
values = st.recursive(
    leaves,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.dictionaries(st.sampled_from(KEYS), inner, max_size=3),
    ),
    max_leaves=8,
)

QUANTITY = re.compile(r"^\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*(.*)$")

# -- mutations ------------------------------------------------------------------------------


def _paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key and index under ``node``, as paths."""
    found = []
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, child in items:
        path = (*prefix, key)
        found.append(path)
        if isinstance(child, dict | list):
            found.extend(_paths(child, path))
    return found


def _at(document: Any, path: tuple) -> Any:
    for step in path:
        document = document[step]
    return document


def _containers(document: dict) -> list[tuple]:
    return [()] + [p for p in _paths(document) if isinstance(_at(document, p), dict | list)]


@st.composite
def mutated(draw: Any) -> tuple[str, dict[str, Any]]:
    name = draw(st.sampled_from(sorted(BASES)))
    document = copy.deepcopy(BASES[name])
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        kind = draw(
            st.sampled_from(
                ["delete", "replace", "replace", "quantity", "unit", "unknown", "duplicate", "time"]
            )
        )
        paths = _paths(document)
        if kind == "delete" and paths:
            path = draw(st.sampled_from(paths))
            parent = _at(document, path[:-1])
            del parent[path[-1]]
        elif kind == "replace" and paths:
            path = draw(st.sampled_from(paths))
            _at(document, path[:-1])[path[-1]] = draw(values)
        elif kind in ("quantity", "unit"):
            strings = [p for p in paths if isinstance(_at(document, p), str)]
            quantity = [p for p in strings if QUANTITY.match(_at(document, p))]
            if not quantity:
                continue
            path = draw(st.sampled_from(quantity))
            number, unit = QUANTITY.match(_at(document, path)).groups()  # type: ignore[union-attr]
            if kind == "quantity":
                number = draw(number_text)
            else:
                unit = draw(st.sampled_from(UNITS))
            _at(document, path[:-1])[path[-1]] = f"{number} {unit}".strip()
        elif kind == "unknown":
            tables = [p for p in _containers(document) if isinstance(_at(document, p), dict)]
            path = draw(st.sampled_from(tables))
            _at(document, path)[draw(st.sampled_from(KEYS))] = draw(values)
        elif kind == "duplicate":
            lists = [p for p in _containers(document) if isinstance(_at(document, p), list)]
            lists = [p for p in lists if _at(document, p)]
            if not lists:
                continue
            path = draw(st.sampled_from(lists))
            items = _at(document, path)
            items.append(copy.deepcopy(draw(st.sampled_from(items))))
        else:  # shorten or shift the time grid
            grid = document.setdefault("time", {})
            if not isinstance(grid, dict):
                continue
            start = draw(st.floats(min_value=-1e3, max_value=1e3) | numbers)
            span = draw(st.floats(min_value=-10, max_value=300) | numbers)
            step = draw(st.floats(min_value=-1, max_value=100) | numbers)
            for key, value in (("start", start), ("stop", start + span), ("step", step)):
                if draw(st.booleans()):
                    grid[key] = f"{value} s"
    return name, document


# -- the checks -----------------------------------------------------------------------------


def _one_line(error: BaseException) -> None:
    message = str(error)
    assert type(error).__name__ not in NOT_ALLOWED_NAMES, f"pydantic leaks: {message!r}"
    assert message.strip(), f"{type(error).__name__} with no message"
    assert "\n" not in message.strip(), f"not one line: {message!r}"


def _validate(path: Path) -> int:
    """``targetacq validate path`` in-process: its exit status (0 or 2, checked)."""
    from targetacq.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            main(["validate", str(path)])
        except SystemExit as done:
            code = done.code
        else:
            code = 0
    lines = err.getvalue().splitlines()
    assert "Traceback" not in err.getvalue(), err.getvalue()
    assert code in (0, 2), f"validate exited {code}: {err.getvalue()!r}"
    if code == 2:
        assert lines, "validate failed with nothing on stderr"
        for line in lines:
            assert line.startswith(PREFIX), f"{line!r} is not {PREFIX!r}..."
    return int(code or 0)


def _few_times(grid: Any) -> np.ndarray:
    """At most three of the time grid's times: start, the next step, stop."""
    start, stop, step = float(grid.start), float(grid.stop), float(grid.step)
    times = [start]
    if start + step <= stop:
        times.append(start + step)
    if stop > times[-1]:
        times.append(stop)
    return np.array(times)


def _attempt(call: Any) -> tuple[Any, BaseException | None]:
    """``call()``, or the ``ValueError``/``TypeError`` it raised (anything else propagates)."""
    try:
        return call(), None
    except ALLOWED as error:
        return None, error


def check(document: dict[str, Any]) -> None:
    from targetacq.run.model_chain import ModelChain
    from targetacq.scenario.plausibility import collected
    from targetacq.scenario.schema import load_scenario

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzz.toml"
        path.write_text(toml_dumps(document), encoding="utf-8")
        code = _validate(path)
        with collected():  # mutated values may be implausible: warned, never refused
            scenario, refused = _attempt(lambda: load_scenario(path))
        what = "load_scenario"
        if refused is None:
            times = _few_times(scenario.time)
            results, refused = _attempt(lambda: ModelChain(scenario).evaluate(times))
            what = "evaluate"
    if refused is not None:
        _one_line(refused)
        assert code == 2, f"validate accepts what {what} refuses: {refused}"
        return
    ds = results.dataset
    for name in [*TASKS, *(f"fused_{t}" for t in TASKS)]:
        p = np.asarray(ds[name].values, dtype=float)
        assert not np.isnan(p).any(), f"{name}: NaN from finite inputs: {p.tolist()}"
        assert ((p >= 0) & (p <= 1)).all(), f"{name}: outside [0, 1]: {p.tolist()}"


@settings(
    max_examples=EXAMPLES_COUNT,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(case=mutated())
def test_fuzzed_scenarios(case: tuple[str, dict[str, Any]]) -> None:
    _, document = case
    check(document)


def test_bundled_examples_pass_unchanged() -> None:
    for document in BASES.values():
        check(copy.deepcopy(document))
