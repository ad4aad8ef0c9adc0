"""The JSON API of the web explorer (FastAPI).

Endpoints
---------
``GET /registries``
    The names the options take (sensor types, criteria, transforms, noise models, bands,
    obscurants, c2nveo bounds, named targets), each with its description and source where the
    registry has them.
``POST /dri``
    The body's keys are the options of ``targetacq dri`` in snake_case, each value the text
    typed on the command line (units included; ``example`` a boolean); the answer is the
    object ``targetacq dri --format json`` prints. One value per option (a comma-separated
    sweep is refused; ``probability`` takes several).
``POST /curves``
    The same body and ``max_range``: the probabilities of detection, recognition and
    identification on a grid of :data:`CURVE_POINTS` ranges, for the page's chart.
``POST /evaluate``
    ``{"scenario": TOML text, "format": "json" | "csv" | "parquet"}``: every sensor × target
    × time of the scenario, as JSON or as a file to download.
``POST /report``
    ``{"scenario": TOML text, "probability": "0.5,0.8,0.95"}``: the HTML report of
    ``targetacq report``.
``POST /step``
    One step of a :class:`targetacq.Simulation` kept in memory between requests (a session):
    the probabilities, the cumulative flags (detected, recognised, identified since the start
    or the last ``reset``; per pair and fused) and the step's events with their ``kind``
    (``first`` or ``reacquired``). ``reset: true`` starts a session again (optionally with
    another ``seed`` or ``run``); that step is a first step.

Warnings
--------
The answers of bodies that carry a scenario (``/evaluate``, ``/report``, the ``/step`` that
starts a session) list the scenario's plausibility warnings (:mod:`targetacq.scenario.plausibility`:
valid values no real sensor has, such as a focal length of ``"100 m"``) as text: in
``"warnings"`` of a JSON answer, and in the ``X-Targetacq-Warnings`` header (a JSON list) of a
file or a page. Every ``/step`` answer lists the step's warnings too (a target in view for less
than the step: :class:`targetacq.run.search.ShortVisitWarning`). Nothing is printed by the server.

Errors
------
Every error is JSON, ``{"detail": [{"loc": [...], "msg": "..."}]}``: 422 for input the library
or the request's schema refuses (malformed JSON, an unknown field with a close match, a value
without its unit, a scenario problem located in the scenario), 413 for a body over
``max_body_bytes``, 404 for an unknown session, 429 for a new session while every kept one is
in use (:data:`SESSION_IDLE_S`), 400 for a request addressed to a host name the application does
not answer (by default only the loopback names, :data:`LOOPBACK_HOSTS`). A message quotes at most
:data:`SHOWN_CHARACTERS` characters of an offending value. Only a bug gives 500.

Files are never read over HTTP: a scenario that names an image, a terrain map or an elevation
model (``[terrain]``), and an MRTD curve file, are refused.
"""

from __future__ import annotations

import json
import math
import re
import secrets
import tempfile
import threading
import time
import tomllib
import warnings
from collections import OrderedDict
from collections.abc import AsyncIterator, Awaitable, Callable, Iterator, MutableMapping, Sequence
from contextlib import asynccontextmanager, contextmanager
from dataclasses import dataclass
from difflib import get_close_matches
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
    create_model,
)
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException as StarletteHTTPException

from targetacq.base.units import shown_text
from targetacq.io.datasets import DOWNLOAD_FORMATS, MEDIA_TYPES
from targetacq.io.files import json_text
from targetacq.run.option_table import RANGE_CASE_OPTIONS, UNCERTAINTY_OPTIONS
from targetacq.scenario.plausibility import collected
from targetacq.scenario.schema import Scenario, ScenarioError, parse_scenario

__all__ = [
    "CURVE_POINTS",
    "LOOPBACK_HOSTS",
    "MAX_SESSIONS",
    "SESSION_IDLE_S",
    "STATIC",
    "create_app",
]

STATIC = Path(__file__).with_name("static")
"""The page's files: ``index.html``, ``app.js``, ``style.css``."""

CURVE_POINTS = 200
"""Ranges on the grid of ``POST /curves``."""

MAX_SESSIONS = 64
"""Simulations kept for ``POST /step`` (see :data:`SESSION_IDLE_S` for which one makes room)."""

SESSION_IDLE_S = 300.0
"""A ``/step`` session idle for longer than this [s] may be dropped to make room for a new one.

When the table holds :data:`MAX_SESSIONS` sessions, a new one takes the place of the least
recently used session if that one has not stepped for this long; otherwise the new session is
refused (429, with ``Retry-After``), and no session that is in use is ever dropped: a client
cannot evict the others' sessions by opening many of its own."""

LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "::1", "[::1]")
"""The host names every application answers by default (the ``Host`` header, port aside)."""

SHOWN_CHARACTERS = 80
"""Most characters of an offending value quoted in an error message (the rest counted)."""

_MESSAGE_CHARACTERS = 2_000  # an error message is cut beyond this, whatever it holds

MAX_PROBABILITIES = 20
"""Probabilities of one ``/dri`` or ``/curves`` request."""

INLINE_PAIRS = 1_000
"""Sessions of at most this many sensor rows × targets step on the server's event loop (no hop
to a worker thread, the cheapest answer); larger ones step in a worker thread, so that a long
step does not hold up other requests."""

WARNINGS_HEADER = "X-Targetacq-Warnings"
"""The header of a file or page answer that lists the scenario's warnings (a JSON list)."""

_HEADER_WARNINGS = 20  # at most this many in the header; the last entry counts the others

_FILES_REFUSED = "files are not read over HTTP"

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]


# --- errors ------------------------------------------------------------------------------------


class ApiError(Exception):
    """A request the API refuses: its HTTP status and its located problems.

    Parameters
    ----------
    status : int
        HTTP status (4xx).
    problems : list of (list, str)
        Each problem's location (``["body", "pitch"]``) and message.
    """

    def __init__(
        self,
        status: int,
        problems: list[tuple[list[Any], str]],
        headers: dict[str, str] | None = None,
    ) -> None:
        super().__init__(problems[0][1] if problems else "")
        self.status = status
        self.problems = problems
        self.headers = headers

    def response(self) -> JSONResponse:
        """The JSON response of this error (every offending value in it shortened)."""
        detail = [
            {"loc": [_bounded_loc(part) for part in loc], "msg": _bounded(msg)}
            for loc, msg in self.problems
        ]
        return JSONResponse({"detail": detail}, status_code=self.status, headers=self.headers)


# A quoted value (not an apostrophe in a word), or a run of text without spaces or quotes, longer
# than SHOWN_CHARACTERS.
_MORE = SHOWN_CHARACTERS + 1
_LONG_VALUE = re.compile(
    rf"(?<!\w)'((?:[^'\\\n]|\\.){{{_MORE},}})'(?!\w)"
    rf"|(?<!\w)\"((?:[^\"\\\n]|\\.){{{_MORE},}})\"(?!\w)"
    rf"|([^\s'\"]{{{_MORE},}})"
)


def _bounded(message: str) -> str:
    """``message`` with every long value in it shortened (:func:`targetacq.base.units.shown_text`:
    its first :data:`SHOWN_CHARACTERS` characters, quoted, and its length), so that an error
    never echoes a whole offending value (a 500 kB session id, field name or unit text)."""
    message = str(message)
    shortened = _LONG_VALUE.sub(
        lambda m: shown_text(next(g for g in m.groups() if g is not None), SHOWN_CHARACTERS),
        message,
    )
    if len(shortened) > _MESSAGE_CHARACTERS:
        shortened = shortened[:_MESSAGE_CHARACTERS] + f"… ({len(shortened):,} characters)"
    return shortened


def _bounded_loc(part: Any) -> Any:
    """A location's part: a key longer than :data:`SHOWN_CHARACTERS` shortened."""
    if isinstance(part, str) and len(part) > SHOWN_CHARACTERS:
        return shown_text(part, SHOWN_CHARACTERS)
    return part


def _scenario_problems(error: ScenarioError) -> list[tuple[list[Any], str]]:
    """Each problem of a scenario error, its location split from its message."""
    problems: list[tuple[list[Any], str]] = []
    for problem in error.problems:
        text = problem.removeprefix("scenario: ")
        where, colon, what = text.partition(": ")
        if colon and " " not in where.strip("[]._"):
            problems.append((["scenario", where], what))
        else:
            problems.append((["scenario"], text))
    return problems


def _named_option(message: str, names: list[str]) -> list[Any]:
    """The location of a library error: the option its message names first (``--pitch``),
    else the whole body."""
    found = []
    for name in names:
        match = re.search(re.escape("--" + name.replace("_", "-")) + r"(?![-\w])", message)
        if match:
            found.append((match.start(), name))
    return ["body", min(found)[1]] if found else ["body"]


@contextmanager
def _library_errors(names: list[str] | None = None) -> Iterator[None]:
    """Turn the library's errors for bad input into 422 responses with located messages."""
    try:
        yield
    except ApiError:
        raise
    except ScenarioError as error:
        raise ApiError(422, _scenario_problems(error)) from None
    except (ValueError, TypeError, KeyError) as error:
        message = str(error.args[0]) if isinstance(error, KeyError) and error.args else str(error)
        raise ApiError(422, [(_named_option(message, names or []), message)]) from None
    except RecursionError:
        raise ApiError(422, [(["body"], "input too deeply nested")]) from None
    except MemoryError as error:
        raise ApiError(
            422, [(["body"], f"not enough memory for this request: {error or 'an allocation'}")]
        ) from None


# --- request bodies ----------------------------------------------------------------------------


class _Body(BaseModel):
    """A request body: unknown fields are refused (with a close match, if any)."""

    # Strict: no text read as a number, no NaN or Infinity literals (a position is a number).
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


_OptionValue = StrictStr | StrictInt | StrictFloat | None


def _option_fields() -> dict[str, Any]:
    """The fields of the range-case options: each the text typed on the command line."""
    fields: dict[str, Any] = {
        spec.name: (_OptionValue, Field(default=None, description=spec.help))
        for spec in RANGE_CASE_OPTIONS
    }
    fields["example"] = (
        bool,
        Field(default=False, description="Use the bundled example camera and target."),
    )
    return fields


def _uncertainty_fields() -> dict[str, Any]:
    """The fields of ``dri --uncertainty`` and its spreads: each the text typed on the command
    line (:data:`targetacq.run.option_table.UNCERTAINTY_OPTIONS`)."""
    return {
        spec.name: (_OptionValue, Field(default=None, description=spec.help))
        for spec in UNCERTAINTY_OPTIONS
    }


DriRequest = create_model(
    "DriRequest",
    __base__=_Body,
    __doc__="The options of ``targetacq dri``, snake_case, values as typed (units included).",
    **_option_fields(),
    **_uncertainty_fields(),
)

CurvesRequest = create_model(
    "CurvesRequest",
    __base__=_Body,
    __doc__="The options of ``targetacq dri`` and the largest range of the curves.",
    **_option_fields(),
    max_range=(
        str | None,
        Field(
            default=None,
            description="Largest range of the curves, e.g. 8km (default: until every task's "
            "probability is below 2 %).",
        ),
    ),
)


_FILE_FORMATS = tuple(name for name in DOWNLOAD_FORMATS if name != "json")
"""The formats of ``POST /evaluate`` answered as a file, from the writers' registry (json is the
arrays themselves)."""

if TYPE_CHECKING:
    EvaluateFormat = str
else:
    EvaluateFormat = Literal[("json", *_FILE_FORMATS)]


class EvaluateRequest(_Body):
    """A scenario to evaluate, and the form of the results."""

    scenario: str = Field(description="The scenario, as the text of a TOML file.")
    format: EvaluateFormat = Field(
        default="json",
        description=f"json: the arrays; {' or '.join(_FILE_FORMATS)}: the table as a file.",
    )


class ReportRequest(_Body):
    """A scenario to report on."""

    scenario: str = Field(description="The scenario, as the text of a TOML file.")
    probability: str | None = Field(
        default=None, description="Probabilities of the DRI table, e.g. 0.5,0.8,0.95."
    )
    max_range: str | None = Field(
        default=None, description="Largest range of the curves, e.g. 8km."
    )


_Triple = Annotated[list[float], Field(min_length=3, max_length=3)]
_Pair = Annotated[list[float], Field(min_length=2, max_length=2)]


class StepRequest(_Body):
    """One step of a simulation: positions at ``time`` of every sensor and target."""

    session: str | None = Field(
        default=None, description="A session from an earlier step; none to start one."
    )
    scenario: str | None = Field(
        default=None,
        description="The scenario (TOML text), to start a session; ignored with a session.",
    )
    reset: bool = Field(
        default=False,
        description="With a session: start it again (no acquisitions, the clock restarted); "
        "this step is then a first step, which only starts the clock.",
    )
    seed: int | None = Field(
        default=None,
        ge=0,
        le=2**128 - 1,
        description="Seed of the random draws, in [0, 2^128), when a session starts (default 0) "
        "or is reset (default: the session's own).",
    )
    run: int | None = Field(
        default=None,
        ge=0,
        lt=2**32,
        description="Which run of the seed's streams, when a session starts or is reset "
        "(default 0): run r is run r of targetacq simulate with the same seed and steps.",
    )
    time: float = Field(description="Time of the step [s].")
    dt: float = Field(description="Length of the step [s]; time − dt is the previous step.")
    sensor_positions: list[_Triple] = Field(description="East, north, up of each sensor [m].")
    target_positions: list[_Triple] = Field(description="East, north, up of each target [m].")
    target_headings: list[float] | None = Field(
        default=None, description="Heading of each target [rad]."
    )
    sensor_pointing: list[_Pair] | None = Field(
        default=None, description="Azimuth and depression of each sensor's axis [rad]."
    )


_BODIES: dict[str, type[BaseModel]] = {
    "/dri": DriRequest,
    "/curves": CurvesRequest,
    "/evaluate": EvaluateRequest,
    "/report": ReportRequest,
    "/step": StepRequest,
}


def _unknown_field(name: str, path: str) -> str:
    """The message for an unknown field of the body of ``path``."""
    model = _BODIES.get(path)
    valid = list(model.model_fields) if model is not None else []
    close = get_close_matches(name, valid, 1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return f"unknown field {shown_text(name)}{hint}; valid: {', '.join(valid)}"


def _validation_problems(error: RequestValidationError, path: str) -> list[tuple[list, str]]:
    problems: list[tuple[list[Any], str]] = []
    for item in error.errors():
        loc = list(item.get("loc", ()))
        if item.get("type") == "extra_forbidden" and loc:
            problems.append((loc, _unknown_field(str(loc[-1]), path)))
        elif item.get("type") == "json_invalid":
            reason = (item.get("ctx") or {}).get("error", "not JSON")
            at = f" (at character {loc[-1]})" if loc and isinstance(loc[-1], int) else ""
            problems.append((["body"], f"malformed JSON: {reason}{at}"))
        else:
            message = str(item.get("msg", "invalid input")).removeprefix("Value error, ")
            problems.append((loc, message))
    return problems


def _parse(model: type[_Body], raw: bytes) -> Any:
    """A request body of ``model`` validated from its JSON bytes in one pass (no parse to
    Python objects first); its problems as FastAPI's, located under ``body``."""
    if not raw.strip():
        raise RequestValidationError(
            [{"type": "missing", "loc": ("body",), "msg": "Field required", "input": None}]
        )
    try:
        return model.model_validate_json(raw)
    except ValidationError as error:
        raise RequestValidationError(
            [{**item, "loc": ("body", *item["loc"])} for item in error.errors(include_url=False)]
        ) from None


def _body_schema(model: type[BaseModel]) -> dict[str, Any]:
    """The OpenAPI request body of a handler that reads ``model`` itself (:func:`_parse`)."""
    schema = model.model_json_schema()
    assert "$defs" not in schema  # inlined: a reference would point into the OpenAPI document
    return {"requestBody": {"required": True, "content": {"application/json": {"schema": schema}}}}


# --- request body size -------------------------------------------------------------------------


class _BodyLimit:
    """ASGI middleware: a request body over ``max_bytes`` (by its ``Content-Length`` or by the
    bytes read) is answered 413, and the application never sees it."""

    def __init__(self, app: ASGIApp, max_bytes: int) -> None:
        self.app = app
        self.max_bytes = max_bytes

    async def _refuse(self, scope: Scope, receive: Receive, send: Send) -> None:
        error = ApiError(
            413,
            [(["body"], f"request body too large: the limit is {self.max_bytes:,} bytes")],
        )
        await error.response()(scope, receive, send)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        for key, value in scope.get("headers", ()):
            if key.lower() == b"content-length":
                try:
                    declared = int(value)
                except ValueError:
                    declared = -1
                if declared > self.max_bytes:
                    await self._refuse(scope, receive, send)
                    return
        chunks: list[bytes] = []
        total = 0
        first: Message | None = None
        while True:
            message = await receive()
            if message["type"] != "http.request":
                first = message  # a disconnect: passed on as it came
                break
            body = message.get("body", b"")
            total += len(body)
            if total > self.max_bytes:
                await self._refuse(scope, receive, send)
                return
            chunks.append(body)
            if not message.get("more_body", False):
                break
        replayed = False

        async def replay() -> Message:
            nonlocal replayed
            if not replayed:
                replayed = True
                if first is not None:
                    return first
                return {"type": "http.request", "body": b"".join(chunks), "more_body": False}
            return await receive()

        await self.app(scope, replay, send)


class _HostCheck:
    """ASGI middleware: a request addressed (``Host`` header, port aside) to a name not in
    ``hosts`` is answered 400, so that a web page elsewhere cannot reach a loopback server
    through a name it re-points at 127.0.0.1 (DNS rebinding). ``"*"`` allows any name."""

    def __init__(self, app: ASGIApp, hosts: Sequence[str]) -> None:
        self.app = app
        self.hosts = {host.lower() for host in hosts}

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket") or "*" in self.hosts:
            await self.app(scope, receive, send)
            return
        host = ""
        for key, value in scope.get("headers", ()):
            if key.lower() == b"host":
                host = value.decode("latin-1")
                break
        name = host.lower()
        if name.startswith("["):
            name = name.partition("]")[0] + "]"
        elif name.count(":") == 1:
            name = name.partition(":")[0]
        if name in self.hosts:
            await self.app(scope, receive, send)
            return
        allowed = ", ".join(sorted(self.hosts))
        error = ApiError(
            400,
            [
                (
                    ["header", "host"],
                    f"this server answers requests addressed to {allowed} only, not "
                    f"{shown_text(host, SHOWN_CHARACTERS)} (create_app(trusted_hosts=...) "
                    "widens it)",
                )
            ],
        )
        await error.response()(scope, receive, send)


# --- the handlers' work ------------------------------------------------------------------------


def _json(document: Any) -> Response:
    """Strict JSON: NaN → null, ±inf → "inf" / "-inf"."""
    return Response(json_text(document, None), media_type="application/json")


def _plain_json(document: Any) -> Response:
    """A document of plain lists, numbers and text as JSON in one ``json.dumps`` (compact);
    through :func:`_json` only where it holds NaN or an infinity."""
    try:
        text = json.dumps(document, allow_nan=False, separators=(",", ":"))
    except ValueError:
        return _json(document)
    return Response(text, media_type="application/json")


def _warnings_header(found: Sequence[str]) -> dict[str, str]:
    """The header listing a scenario's warnings on a file or page answer (none: no header)."""
    if not found:
        return {}
    shown = list(found[:_HEADER_WARNINGS])
    if len(found) > _HEADER_WARNINGS:
        shown.append(f"and {len(found) - _HEADER_WARNINGS} more warnings")
    return {WARNINGS_HEADER: json.dumps(shown)}  # ASCII: escapes anything else


_CAPTURE = threading.Lock()


@contextmanager
def _step_warnings() -> Iterator[list[str]]:
    """The user warnings a step emits (a short visit), as text, instead of printed by the
    server. The process's warning state is shared, so one capture runs at a time."""
    found: list[str] = []
    with _CAPTURE, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield found
    found += [str(w.message) for w in caught if issubclass(w.category, UserWarning)]


def _case_options(body: BaseModel) -> dict[str, Any]:
    """The body's range-case options as the CLI hands them on: text, or None; ``example``."""
    options: dict[str, Any] = {}
    for spec in RANGE_CASE_OPTIONS:
        value = getattr(body, spec.name)
        if isinstance(value, bool):
            raise ApiError(422, [(["body", spec.name], f"{spec.flag} takes text, not a boolean")])
        options[spec.name] = None if value is None else str(value)
    if options.get("mrtd") is not None:
        raise ApiError(422, [(["body", "mrtd"], f"--mrtd names a file, and {_FILES_REFUSED}")])
    options["example"] = bool(body.example)  # type: ignore[attr-defined]
    return options


_OPTION_NAMES = [spec.name for spec in RANGE_CASE_OPTIONS]
_UNCERTAINTY_NAMES = [spec.name for spec in UNCERTAINTY_OPTIONS]

MAX_WEB_SAMPLES = 5000
"""Most Monte Carlo samples of one ``/dri`` request (the command line takes more)."""


def _uncertainty(body: BaseModel) -> Any:
    """The Monte Carlo of a ``/dri`` body's uncertainty options, as ``targetacq dri`` reads
    them (:func:`targetacq.run.uncertainty.read_uncertainty`), or None without ``uncertainty``."""
    from targetacq.run.uncertainty import read_uncertainty

    given = {}
    for name in _UNCERTAINTY_NAMES:
        value = getattr(body, name)
        if isinstance(value, bool):
            raise ApiError(422, [(["body", name], f"{name} takes text, not a boolean")])
        given[name] = None if value is None else str(value)
    with _library_errors(_UNCERTAINTY_NAMES):
        uncertainty = read_uncertainty(given)
    if uncertainty is not None and uncertainty.samples > MAX_WEB_SAMPLES:
        raise ApiError(
            422,
            [
                (
                    ["body", "uncertainty"],
                    f"at most {MAX_WEB_SAMPLES} samples over HTTP; got {uncertainty.samples} "
                    "(targetacq dri --uncertainty takes up to 100000)",
                )
            ],
        )
    return uncertainty


def _setup(body: BaseModel) -> Any:
    """The range setup of the body's options, as ``targetacq dri`` builds it."""
    from targetacq.run.option_table import typed_options
    from targetacq.run.range_options import range_setup

    options = _case_options(body)
    listed = (options.get("probability") or "").count(",") + 1
    if listed > MAX_PROBABILITIES:
        raise ApiError(
            422,
            [(["body", "probability"], f"at most {MAX_PROBABILITIES} probabilities; got {listed}")],
        )
    with _library_errors(_OPTION_NAMES):
        return range_setup(typed_options(options, "dri"), "0.5")


def _no_curves(setup: Any) -> str | None:
    """Why a case has no probability curves (None when it has): a pixel-density criterion
    gives thresholds, a detection-only transform needs the clutter given with another one."""
    from targetacq.acquisition.transforms import get_transform

    if not setup.criterion.gives_probabilities:
        return f"criterion {setup.criterion.name} gives pixel-density ranges, not probabilities"
    chosen = get_transform(setup.case.transform)
    if chosen.tasks == ("detection",):
        return (
            f"transform {chosen.name} covers detection in clutter only: its ranges are in the "
            "table; choose a transform for all tasks (e.g. ttpf) with the clutter for curves"
        )
    return None


def _curves(body: BaseModel) -> dict[str, Any]:
    """The range-performance curves of the body's one case."""
    from targetacq.core import ranges
    from targetacq.reports.content import FLOOR, MAX_AUTO_RANGE, case_title
    from targetacq.run.range_options import option_quantity

    setup = _setup(body)
    unsupported = _no_curves(setup)
    if unsupported is not None:  # the table (/dri) has ranges; there are no curves to draw
        return {
            "range_m": [],
            **dict.fromkeys(("detection", "recognition", "identification")),
            "case": case_title(setup),
            "note": unsupported,
        }
    max_range = body.max_range  # type: ignore[attr-defined]
    with _library_errors([*_OPTION_NAMES, "max_range"]):
        if max_range is not None:
            r_max = option_quantity(max_range, "length", "--max-range")
        else:
            reach = [
                float(r)
                for p in (FLOOR, min(setup.probabilities))
                for r in ranges.case_ranges(setup.case, p).values()
            ]
            finite = [r for r in reach if math.isfinite(r) and r > 0]
            r_max = min(1.05 * max(finite), MAX_AUTO_RANGE) if finite else 10e3
        grid = [r_max * (k + 1) / CURVE_POINTS for k in range(CURVE_POINTS)]
        label = case_title(setup)
        curves = ranges.range_performance(grid, {label: setup.case}, setup.probabilities).curves
    out: dict[str, Any] = {"range_m": grid}
    for task in ("detection", "recognition", "identification"):
        out[task] = (
            [float(p) for p in curves[task].sel(case=label).values] if task in curves else None
        )
    out["case"] = label
    return out


def _scenario(text: str) -> tuple[Scenario, list[str]]:
    """A scenario from TOML text, and its plausibility warnings; one that names a file (an
    image, a terrain map, an elevation model, an MRTD curve) is refused."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ApiError(422, [(["body", "scenario"], f"malformed TOML: {error}")]) from None
    except RecursionError:
        raise ApiError(422, [(["body", "scenario"], "malformed TOML: nested too deeply")]) from None
    background = data.get("background")
    if isinstance(background, dict):
        for key in ("image", "terrain"):
            if background.get(key) is not None:
                raise ApiError(
                    422,
                    [
                        (
                            ["scenario", f"background.{key}"],
                            f"{_FILES_REFUSED}: give a scenario without background.{key} "
                            "(run it with targetacq evaluate FILE instead)",
                        )
                    ],
                )
    if data.get("terrain") is not None:  # [terrain] elevation names a grid file
        raise ApiError(
            422,
            [
                (
                    ["scenario", "terrain.elevation"],
                    f"{_FILES_REFUSED}: give a scenario without [terrain] (run it with "
                    "targetacq evaluate FILE or the step API instead)",
                )
            ],
        )
    sensors = data.get("sensors")
    for k, sensor in enumerate(sensors if isinstance(sensors, list) else []):
        if isinstance(sensor, dict) and sensor.get("mrtd") is not None:
            raise ApiError(
                422,
                [
                    (
                        ["scenario", f"sensors[{k}].mrtd"],
                        f"{_FILES_REFUSED}: give a scenario without sensors[{k}].mrtd (run it "
                        "with targetacq evaluate FILE instead)",
                    )
                ],
            )
    targets = data.get("targets")
    for k, target in enumerate(targets if isinstance(targets, list) else []):
        if isinstance(target, dict) and isinstance(target.get("signature_table"), str):
            raise ApiError(
                422,
                [
                    (
                        ["scenario", f"targets[{k}].signature_table"],
                        f"{_FILES_REFUSED}: write the table in the scenario (signature_table = "
                        "{azimuth = [...], elevation = [...], temperature = [[...]]}) or run it "
                        "with targetacq evaluate FILE",
                    )
                ],
            )
    with _library_errors(), collected() as found:
        scenario = parse_scenario(data, source="scenario")
    return scenario, [message.removeprefix("scenario: ") for message in found]


def _check_work(scenario: Scenario, limit: int, *, times: bool = True) -> None:
    """A scenario whose evaluation (sensor rows × targets × times) exceeds ``limit`` is refused:
    the body limit bounds what is sent, this what it asks to be computed."""
    from targetacq.core import sensor_rows

    pairs = len(sensor_rows(scenario)) * len(scenario.targets)
    count = pairs * (scenario.time.count if times else 1)
    if count > limit:
        where = ["scenario", "time.step"] if times else ["scenario", "targets"]
        what = "sensor rows × targets × times" if times else "sensor rows × targets"
        raise ApiError(
            422,
            [
                (
                    where,
                    f"the scenario asks for {count:,} evaluations ({what}); the server's limit "
                    f"is {limit:,}: run it with targetacq evaluate instead",
                )
            ],
        )


FILE_ROW_COST = 4
"""What one row of an ``/evaluate`` file (CSV, Parquet) costs, in evaluations: writing the table
takes about four times as long as evaluating it (measured: 10 µs per evaluation as JSON, 40 µs
as CSV)."""

REPORT_CURVE_POINTS = 600
"""Ranges of a report's range-performance curves (``targetacq report``)."""


def _check_file_work(scenario: Scenario, limit: int) -> None:
    """An ``/evaluate`` file whose rows (sensor rows × targets × times), each weighted by
    :data:`FILE_ROW_COST`, exceed ``limit`` evaluations is refused before any work."""
    from targetacq.core import sensor_rows

    rows = len(sensor_rows(scenario)) * len(scenario.targets) * int(scenario.time.count)
    if rows * FILE_ROW_COST > limit:
        raise ApiError(
            422,
            [
                (
                    ["scenario", "time.step"],
                    f"the scenario's file would have {rows:,} rows (sensor rows × targets × "
                    f"times), each costing {FILE_ROW_COST} evaluations to write: "
                    f"{rows * FILE_ROW_COST:,}; the server's limit is {limit:,} evaluations: "
                    "ask for JSON, or run it with targetacq evaluate --out instead",
                )
            ],
        )


def _check_report_work(scenario: Scenario, limit: int) -> None:
    """A report whose work exceeds ``limit`` is refused before any work: sensor rows × targets ×
    (:data:`REPORT_CURVE_POINTS` curve ranges + the scenario's times + the simulated runs × their
    steps), each a pair's evaluation or draw at one range or time."""
    from targetacq.core import sensor_rows
    from targetacq.reports.content import SIMULATION_RUNS, SIMULATION_STEPS

    pairs = len(sensor_rows(scenario)) * len(scenario.targets)
    times = int(scenario.time.count)
    duration = float(scenario.time.stop - scenario.time.start)
    steps = max(times - 1, SIMULATION_STEPS) if duration > 0 else 0
    work = pairs * (REPORT_CURVE_POINTS + times + SIMULATION_RUNS * steps)
    if work > limit:
        where = "time.step" if times - 1 > SIMULATION_STEPS else "targets"
        raise ApiError(
            422,
            [
                (
                    ["scenario", where],
                    f"the report asks for {work:,} pair evaluations ({pairs:,} sensor rows × "
                    f"targets × ({REPORT_CURVE_POINTS} curve ranges + {times:,} times + "
                    f"{SIMULATION_RUNS} simulated runs × {steps:,} steps)); the server's "
                    f"limit is {limit:,}: run it with targetacq report instead",
                )
            ],
        )


def _evaluate(body: EvaluateRequest, max_evaluations: int) -> Response:
    from targetacq.run.model_chain import ModelChain

    scenario, found = _scenario(body.scenario)
    _check_work(scenario, max_evaluations)
    if body.format != "json":
        _check_file_work(scenario, max_evaluations)
    with _library_errors():
        results = ModelChain(scenario).evaluate()
        if body.format != "json":
            with tempfile.TemporaryDirectory(prefix="targetacq-web-") as folder:
                name = f"results.{body.format}"
                written = results.write(Path(folder) / name)
                content = written.read_bytes()
            return Response(
                content,
                media_type=MEDIA_TYPES[body.format],
                headers={
                    "Content-Disposition": f"attachment; filename={name}",
                    **_warnings_header(found),
                },
            )
    ds = results.dataset
    document: dict[str, Any] = {
        "name": scenario.name,
        "time_s": ds["time"].values,
        "sensors": [str(s) for s in ds["sensor"].values],
        "targets": [str(t) for t in ds["target"].values],
    }
    for task in ("detection", "recognition", "identification"):
        document[f"fused_{task}"] = ds[f"fused_{task}"].transpose("target", "time").values
    for task in ("detection", "recognition", "identification"):
        document[task] = ds[task].transpose("sensor", "target", "time").values
    document["warnings"] = found
    return _json(document)


def _report(body: ReportRequest, max_evaluations: int, max_report_work: int) -> Response:
    from targetacq import __version__
    from targetacq.io.html_report import render_report
    from targetacq.reports.content import REPORT_PROBABILITIES, scenario_report
    from targetacq.run.range_options import option_probabilities

    scenario, found = _scenario(body.scenario)  # refuses files and locates problems first
    _check_work(scenario, max_evaluations)
    _check_report_work(scenario, max_report_work)
    with _library_errors(["probability", "max_range"]):
        probabilities = option_probabilities(body.probability or REPORT_PROBABILITIES)
        with tempfile.TemporaryDirectory(prefix="targetacq-web-") as folder:
            path = Path(folder) / "scenario.toml"
            path.write_text(body.scenario, encoding="utf-8")
            title = scenario.name or "scenario"
            with collected():  # the file read again: its warnings are listed already
                heading, performance, sections, figures, captions = scenario_report(
                    str(path), body.max_range, title, probabilities
                )
        sections = {
            section: {
                key: ("scenario (sent to the explorer)" if value == str(path) else value)
                for key, value in items.items()
            }
            for section, items in sections.items()
        }
        page = render_report(
            performance, sections, figures, title=heading, version=__version__, captions=captions
        )
    return Response(page, media_type="text/html", headers=_warnings_header(found))


@dataclass
class _Session:
    simulation: Any
    lock: threading.Lock
    used: float  # when it was last asked for [s, monotonic clock]


class _Sessions:
    """The simulations of ``POST /step``, by id: at most ``limit``; when full, a new one takes
    the place of the least recently used session only if that one has been idle for more than
    ``idle`` seconds, and is refused (429) otherwise (:data:`SESSION_IDLE_S`)."""

    def __init__(
        self,
        limit: int = MAX_SESSIONS,
        idle: float = SESSION_IDLE_S,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.limit = limit
        self.idle = idle
        self.clock = clock
        self._items: OrderedDict[str, _Session] = OrderedDict()  # least recently used first
        self._lock = threading.Lock()

    def _make_room(self, now: float) -> None:
        """Drop idle sessions until one more fits; a 429 when every session is in use."""
        while len(self._items) >= self.limit:
            oldest = next(iter(self._items.values()))
            idle_for = now - oldest.used
            if idle_for <= self.idle:
                wait = max(1, math.ceil(self.idle - idle_for))
                raise ApiError(
                    429,
                    [
                        (
                            ["body", "session"],
                            f"no room for a new session: the server keeps at most {self.limit} "
                            f"sessions and each has stepped within the last {self.idle:g} s (only "
                            f"a session idle for longer is dropped to make room); retry in "
                            f"{wait} s, or go on with a session you have (reset: true starts it "
                            "again)",
                        )
                    ],
                    headers={"Retry-After": str(wait)},
                )
            self._items.popitem(last=False)

    def check_room(self) -> None:
        """Refuse (429) before any work when a new session could not be kept."""
        with self._lock:
            self._make_room(self.clock())

    def add(self, simulation: Any) -> str:
        key = secrets.token_urlsafe(16)
        with self._lock:
            now = self.clock()
            self._make_room(now)
            self._items[key] = _Session(simulation, threading.Lock(), now)
        return key

    def peek(self, key: str) -> _Session | None:
        """The session ``key``, or None (not counted as a use)."""
        with self._lock:
            return self._items.get(key)

    def get(self, key: str) -> _Session:
        """The session ``key``, marked as used now; a 404 when there is none."""
        with self._lock:
            session = self._items.get(key)
            if session is not None:
                session.used = self.clock()
                self._items.move_to_end(key)
        if session is None:
            raise ApiError(
                404,
                [
                    (
                        ["body", "session"],
                        f"unknown session {shown_text(key, SHOWN_CHARACTERS)}: it never existed "
                        f"or was dropped (a session idle for more than {self.idle:g} s is "
                        "dropped when room is needed); start a new one by sending the scenario "
                        "without a session",
                    )
                ],
            )
        return session


_STEP_ARRAYS = {
    "sensor_positions": 3,
    "target_positions": 3,
    "target_headings": 1,
    "sensor_pointing": 2,
}
"""The arrays of a ``/step`` body and the numbers in each of their rows (checked by the body's
schema), so that their sizes are counted without walking them."""


def _check_sizes(body: StepRequest, max_elements: int) -> None:
    for name, width in _STEP_ARRAYS.items():
        value = getattr(body, name)
        count = 0 if value is None else len(value) * width
        if count > max_elements:
            raise ApiError(
                422,
                [(["body", name], f"{name} has {count:,} numbers; the limit is {max_elements:,}")],
            )


def _session(body: StepRequest, sessions: _Sessions, max_elements: int) -> tuple[str, list[str]]:
    """The session of a ``/step`` body (started from its scenario when it names none), and the
    scenario's warnings when it starts one."""
    from targetacq.run.simulation import Simulation

    if body.session is not None:
        if not body.reset:
            for name in ("seed", "run"):
                if getattr(body, name) is not None:
                    raise ApiError(
                        422,
                        [
                            (
                                ["body", name],
                                f"{name} is taken when a session starts, or with reset: true; "
                                "a session's later steps go on with its own",
                            )
                        ],
                    )
        sessions.get(body.session)  # an unknown session is a 404 before any work
        return body.session, []
    if body.reset:
        raise ApiError(
            422,
            [
                (
                    ["body", "reset"],
                    "reset: true starts a session again: give its session (a body with the "
                    "scenario and no session starts a new one)",
                )
            ],
        )
    if body.scenario is None:
        raise ApiError(422, [(["body", "scenario"], "give the scenario (TOML text) or a session")])
    sessions.check_room()  # a full table of sessions in use: refused before any work
    scenario, found = _scenario(body.scenario)
    _check_work(scenario, max_elements, times=False)  # a session keeps its pairs' state
    with _library_errors(["seed", "run"]):
        simulation = Simulation.from_scenario(scenario, seed=body.seed or 0)
        if body.run:
            simulation.reset(run=body.run)
    return sessions.add(simulation), found


def _step_answer(body: StepRequest, key: str, sessions: _Sessions, found: list[str]) -> Response:
    """Step the session ``key`` (after its reset, if asked) and answer the step as JSON."""
    from targetacq.run.simulation import TASKS

    session = sessions.get(key)
    with session.lock, _library_errors(list(_STEP_ARRAYS)), _step_warnings() as raised:
        simulation = session.simulation
        if body.reset:
            simulation.reset(seed=body.seed, run=body.run or 0)
        result = simulation.step(
            body.time,
            body.dt,
            body.sensor_positions,
            body.target_positions,
            target_headings=body.target_headings,
            sensor_pointing=body.sensor_pointing,
        )
    false = result.false_detections
    document: dict[str, Any] = {
        "session": key,
        "time": result.time,
        "sensors": list(simulation.sensors),
        "targets": list(simulation.targets),
    }
    # Plain lists (tolist), written by one json.dumps: no per-element conversion.
    for name in (
        *TASKS,
        *(f"fused_{task}" for task in TASKS),
        "in_view",
        *_FLAGS,
        *(f"fused_{flag}" for flag in _FLAGS),
    ):
        document[name] = getattr(result, name).tolist()
    document["events"] = [event._asdict() for event in result.events]
    document["false_detections"] = [
        {"sensor": str(s), "time": float(t), "x": float(p[0]), "y": float(p[1]), "z": float(p[2])}
        for s, t, p in zip(false.sensor, false.time, false.position, strict=True)
    ]
    document["warnings"] = found + raised
    return _plain_json(document)


_FLAGS = ("detected", "recognised", "identified")
"""The cumulative flags of :class:`targetacq.run.simulation.StepResult` (and ``fused_`` each)."""


def _step(body: StepRequest, sessions: _Sessions, max_elements: int) -> Response:
    """``POST /step`` whole: the session (maybe a new one), its step, the answer."""
    _check_sizes(body, max_elements)
    key, found = _session(body, sessions, max_elements)
    return _step_answer(body, key, sessions, found)


def _pairs(body: StepRequest, sessions: _Sessions) -> float:
    """Sensor rows × targets of the body's session (inf for a new or unknown one)."""
    session = None if body.session is None else sessions.peek(body.session)
    if session is None:
        return math.inf
    simulation = session.simulation
    return float(len(simulation.sensors) * len(simulation.targets))


def _registries() -> dict[str, Any]:
    """Every registry's names, with descriptions and sources where it has them."""
    from targetacq.acquisition.criteria import CRITERIA
    from targetacq.acquisition.path_noise import NOISE_MODELS, SNR_LAWS
    from targetacq.acquisition.transforms import C2NVEO_BOUNDS, TRANSFORMS
    from targetacq.physics.atmosphere import EXTINCTION_LEVELS, OBSCURANTS
    from targetacq.physics.bands import BANDS
    from targetacq.physics.targets import TARGETS
    from targetacq.sensors import SENSOR_TYPES

    def items(registry: Any) -> list[dict[str, Any]]:
        out = []
        for name in registry:
            entry = registry[name] if hasattr(registry, "keys") else None
            item: dict[str, Any] = {"name": name}
            for key in ("description", "source"):
                text = getattr(entry, key, None)
                if isinstance(text, str) and text:
                    item[key] = text
            out.append(item)
        return out

    targets = items(TARGETS)
    for item in targets:
        item["critical_dimension_m"] = TARGETS[item["name"]].critical_dimension
    bands = [{"name": name, "limits_m": list(limits)} for name, limits in BANDS.items()]
    obscurants = [{"name": name, "levels": list(EXTINCTION_LEVELS)} for name in OBSCURANTS]
    return {
        "sensor_types": items(SENSOR_TYPES),
        "criteria": items(CRITERIA),
        "transforms": items(TRANSFORMS),
        "noise_models": items(NOISE_MODELS),
        "snr_laws": items(SNR_LAWS),
        "bands": bands,
        "obscurants": obscurants,
        "bounds": items(C2NVEO_BOUNDS),
        "targets": targets,
    }


_WARM_CASE = {"pitch": "17um", "focal_length": "50mm", "critical_dimension": "2.3m"}


def _warm() -> None:
    """Import and build what the first answers need (the first ``/curves`` imports xarray,
    pandas and the range solver's modules: about 1.3 s of one core, 4.5 s on a busy machine),
    so that the page's first chart does not wait for it. Run at start-up, before the server
    answers; a failure here is left to the request that meets it."""
    try:
        _registries()
        _curves(CurvesRequest(**_WARM_CASE))
    except Exception:  # the real request reports any problem
        pass


# --- the application ---------------------------------------------------------------------------


def create_app(
    *,
    max_body_bytes: int = 1_000_000,
    max_elements: int = 100_000,
    max_evaluations: int = 500_000,
    max_report_work: int = 2_000_000,
    trusted_hosts: Sequence[str] | None = LOOPBACK_HOSTS,
    max_sessions: int = MAX_SESSIONS,
    session_idle_s: float = SESSION_IDLE_S,
    warm: bool = True,
) -> FastAPI:
    """The explorer's application: the JSON API and the page.

    Parameters
    ----------
    max_body_bytes : int
        Largest request body [bytes]; a larger one is answered 413.
    max_elements : int
        Most numbers in one array of a request, and most sensor rows × targets of a ``/step``
        session; more is answered 422.
    max_evaluations : int
        Most sensor rows × targets × times of one ``/evaluate`` or ``/report``, a file's rows
        each counted :data:`FILE_ROW_COST` times (the default takes about 5 s on one core
        either way); more is answered 422 before any work (a small file can ask for a large
        run).
    max_report_work : int
        Most pair evaluations of one ``/report``: sensor rows × targets × (curve ranges +
        times + simulated runs × steps), about 120,000 per pair for a short scenario (the
        default takes about 15 pairs, 10–15 s); more is answered 422 before any work.
    trusted_hosts : sequence of str, optional
        The host names a request may be addressed to (its ``Host`` header, port aside); any
        other is answered 400, so that a web page elsewhere cannot reach the server by DNS
        rebinding. Default: the loopback names (:data:`LOOPBACK_HOSTS`); widen it for a server
        reachable by other names; None or ``["*"]``: any name.
    max_sessions : int
        Most ``/step`` sessions kept (:data:`MAX_SESSIONS`).
    session_idle_s : float
        A session idle for longer than this [s] may be dropped to make room for a new one;
        while every session is in use, a new one is refused with 429 (:data:`SESSION_IDLE_S`).
    warm : bool
        At start-up (the server's lifespan, before it answers), import what the answers need
        and compute one small case, so that the first chart is answered at once rather than
        after the imports.

    Returns
    -------
    fastapi.FastAPI
        Serve it with uvicorn (``targetacq serve``), or test it with FastAPI's ``TestClient``.

    Examples
    --------
    >>> app = create_app(max_body_bytes=100_000)  # answers loopback names only
    >>> sorted(path for path in app.openapi()["paths"])
    ['/curves', '/dri', '/evaluate', '/registries', '/report', '/step']
    """
    from targetacq import __version__

    if min(max_body_bytes, max_elements, max_evaluations, max_report_work, max_sessions) < 1:
        raise ValueError(
            "max_body_bytes, max_elements, max_evaluations, max_report_work and max_sessions "
            "must be >= 1"
        )
    if not session_idle_s >= 0:
        raise ValueError(f"session_idle_s must be >= 0 [s]; got {session_idle_s!r}")

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        # Before the server answers anything: warming up beside the first requests would race
        # their imports of the same modules.
        if warm:
            await run_in_threadpool(_warm)
        yield

    app = FastAPI(
        lifespan=lifespan,
        title="targetacq explorer",
        version=__version__,
        description="Probabilities of detection, recognition and identification of targets "
        "by imaging sensors (Sonesson 2004): the library's range cases, scenarios and "
        "simulations over JSON.",
    )
    app.add_middleware(_BodyLimit, max_bytes=max_body_bytes)
    if trusted_hosts is not None:
        if isinstance(trusted_hosts, str):
            raise TypeError("trusted_hosts takes a sequence of host names, not one string")
        app.add_middleware(_HostCheck, hosts=list(trusted_hosts))
    sessions = _Sessions(max_sessions, session_idle_s)
    app.state.sessions = sessions

    @app.exception_handler(ApiError)
    async def api_error(request: Request, error: ApiError) -> JSONResponse:
        return error.response()

    @app.exception_handler(StarletteHTTPException)
    async def http_error(request: Request, error: StarletteHTTPException) -> JSONResponse:
        # The framework's own answers (no such path, a body that is not JSON) in the same
        # shape as every other error: a list of located messages.
        if error.status_code == 400:
            return ApiError(422, [(["body"], f"malformed JSON: {error.detail}")]).response()
        return ApiError(error.status_code, [([], str(error.detail))]).response()

    @app.exception_handler(RequestValidationError)
    async def invalid_request(request: Request, error: RequestValidationError) -> JSONResponse:
        return ApiError(422, _validation_problems(error, request.url.path)).response()

    @app.exception_handler(Exception)
    async def internal_error(request: Request, error: Exception) -> JSONResponse:
        return JSONResponse(
            {"detail": [{"loc": [], "msg": f"internal error ({type(error).__name__})"}]},
            status_code=500,
        )

    @app.get("/", include_in_schema=False)
    def index() -> Response:
        page = STATIC / "index.html"
        if not page.is_file():
            return JSONResponse(
                {"detail": [{"loc": [], "msg": "the page is not installed"}]}, status_code=404
            )
        return FileResponse(page, media_type="text/html")

    if STATIC.is_dir():
        app.mount("/static", StaticFiles(directory=STATIC), name="static")

    @app.get("/registries", summary="The names the options take")
    def registries() -> Response:
        return _json(_registries())

    @app.post("/dri", summary="DRI ranges of one sensor and target (targetacq dri)")
    def dri(body: DriRequest) -> Response:  # type: ignore[valid-type]
        from targetacq.run.range_options import dri_report
        from targetacq.run.uncertainty import uncertainty_report

        setup = _setup(body)
        uncertainty = _uncertainty(body)
        with _library_errors(_OPTION_NAMES):
            if uncertainty is not None:
                return _json(uncertainty_report(setup, uncertainty))
            return _json(dri_report(setup))

    @app.post("/curves", summary="Probability against range of one sensor and target")
    def curves(body: CurvesRequest) -> Response:  # type: ignore[valid-type]
        return _json(_curves(body))

    @app.post("/evaluate", summary="Every sensor × target × time of a scenario")
    def evaluate(body: EvaluateRequest) -> Response:
        return _evaluate(body, max_evaluations)

    @app.post("/report", summary="The HTML report of a scenario (targetacq report)")
    def report(body: ReportRequest) -> Response:
        return _report(body, max_evaluations, max_report_work)

    @app.post(
        "/step",
        summary="One step of a simulation kept between requests",
        openapi_extra=_body_schema(StepRequest),
    )
    async def step(request: Request) -> Response:
        # The body validated from its bytes in one pass; a small session's step runs here,
        # on the event loop (no hop to a worker thread), a large one or a new session in a
        # worker thread.
        body = _parse(StepRequest, await request.body())
        if _pairs(body, sessions) <= INLINE_PAIRS:
            return _step(body, sessions, max_elements)
        return await run_in_threadpool(_step, body, sessions, max_elements)

    return app
