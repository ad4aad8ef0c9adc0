"""Render targetacq's registries as reStructuredText tables at build time.

Every row comes from the registry itself (its entries' ``source`` and ``description`` fields,
the provenance headers of the bundled data files, or the attribute docstring of a name tuple),
so nothing is typed twice. :func:`registries` is the generator; the Sphinx hook writes one
``.rst.inc`` file per registry under ``docs/generated/registries``.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["RegistryTable", "module_page", "registries", "render", "write_pages", "write_tables"]


@dataclass(frozen=True)
class RegistryTable:
    """One registry as a table: a file stem, a title, the registry's Python name, rows."""

    stem: str
    title: str
    origin: str
    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    intro: str = ""


def _attr_doc(module: str, name: str) -> str:
    """The docstring written under a module-level name (``NAME = ...`` then ``\"\"\"...\"\"\"``)."""
    from sphinx.pycode import ModuleAnalyzer

    docs = ModuleAnalyzer.for_module(module).find_attr_docs()
    return " ".join(line.strip() for line in docs.get(("", name), []) if line.strip())


def _first_line(text: str) -> str:
    return text.strip().splitlines()[0] if text.strip() else ""


def _number(value: float) -> str:
    return f"{value:g}"


def _criteria() -> RegistryTable:
    from targetacq.acquisition.criteria import CRITERIA, TASKS

    rows = []
    for name, c in CRITERIA.items():
        unit = "cycles (N50)" if c.kind == "cycles" else "pixels/m"
        values = ", ".join(
            f"{task} {_number(c.thresholds[task])}" for task in TASKS if task in c.thresholds
        )
        extra = [t for t in c.thresholds if t not in TASKS]
        values += "".join(f", {t} {_number(c.thresholds[t])}" for t in extra)
        rows.append((name, unit, values, c.source))
    return RegistryTable(
        "criteria",
        "Criteria sets",
        "targetacq.acquisition.criteria.CRITERIA",
        ("name", "thresholds in", "values", "source"),
        tuple(rows),
        _attr_doc("targetacq.acquisition.criteria", "CRITERIA"),
    )


def _transforms() -> RegistryTable:
    from targetacq.acquisition.transforms import TRANSFORMS

    rows = []
    for name, t in TRANSFORMS.items():
        tasks = "all" if t.tasks is None else ", ".join(t.tasks)
        options = ", ".join(f"{k}={v!r}" for k, v in t.options.items()) or "none"
        rows.append((name, tasks, options, t.source))
    return RegistryTable(
        "transforms",
        "Transforms",
        "targetacq.acquisition.transforms.TRANSFORMS",
        ("name", "tasks", "options (defaults)", "source"),
        tuple(rows),
        _attr_doc("targetacq.acquisition.transforms", "TRANSFORMS"),
    )


def _noise_models() -> RegistryTable:
    from targetacq.acquisition.path_noise import NOISE_MODELS

    rows = tuple(
        (name, "yes" if m.combines_with_clutter else "no", m.source)
        for name, m in NOISE_MODELS.items()
    )
    return RegistryTable(
        "noise_models",
        "Noise models",
        "targetacq.acquisition.path_noise.NOISE_MODELS",
        ("name", "combines with clutter", "what it is and its source"),
        rows,
        _attr_doc("targetacq.acquisition.path_noise", "NOISE_MODELS"),
    )


def _snr_laws() -> RegistryTable:
    from targetacq.acquisition.path_noise import SNR_LAWS

    rows = tuple(
        (name, "none" if law.threshold is None else f"Φ(SNR − {law.threshold:g})", law.source)
        for name, law in SNR_LAWS.items()
    )
    return RegistryTable(
        "snr_laws",
        "SNR laws",
        "targetacq.acquisition.path_noise.SNR_LAWS",
        ("name", "detection threshold", "what it is and its source"),
        rows,
        _attr_doc("targetacq.acquisition.path_noise", "SNR_LAWS"),
    )


def _sensor_types() -> RegistryTable:
    from targetacq.sensors import SENSOR_TYPES

    rows = tuple((name, s.description, s.source) for name, s in SENSOR_TYPES.items())
    return RegistryTable(
        "sensor_types",
        "Sensor types",
        "targetacq.sensors.SENSOR_TYPES",
        ("name", "what it is", "source"),
        rows,
        _attr_doc("targetacq.sensors", "SENSOR_TYPES"),
    )


def _obscurants() -> RegistryTable:
    from targetacq.base.tables import load_table
    from targetacq.physics.atmosphere import OBSCURANTS
    from targetacq.physics.bands import BANDS

    table = load_table("extinction")
    cells = table.keyed_ranges(("obscurant", "band"), "low_np_per_km", "high_np_per_km")
    rows = []
    for obscurant in OBSCURANTS:
        values = []
        for band in BANDS:
            low, high = cells[(obscurant, band)]
            values.append(_number(low) if low == high else f"{_number(low)}–{_number(high)}")
        rows.append((obscurant, *values, "data/extinction.csv"))
    return RegistryTable(
        "obscurants",
        "Obscurants (extinction in Np/km)",
        "targetacq.physics.atmosphere.OBSCURANTS",
        ("name", *BANDS, "source"),
        tuple(rows),
        _attr_doc("targetacq.physics.atmosphere", "OBSCURANTS")
        + " Source: "
        + " ".join(table.provenance.split()),
    )


def _levels() -> RegistryTable:
    from targetacq.physics.atmosphere import EXTINCTION_LEVELS

    what = _attr_doc("targetacq.physics.atmosphere", "EXTINCTION_LEVELS")
    rows = tuple((level, str(i + 1)) for i, level in enumerate(EXTINCTION_LEVELS))
    return RegistryTable(
        "extinction_levels",
        "Extinction levels",
        "targetacq.physics.atmosphere.EXTINCTION_LEVELS",
        ("name", "position in the list"),
        rows,
        what,
    )


def _visibility() -> RegistryTable:
    from targetacq.physics.atmosphere import VISIBILITY_CONVENTIONS

    rows = tuple((name, f"{value:.4f}") for name, value in VISIBILITY_CONVENTIONS.items())
    return RegistryTable(
        "visibility_conventions",
        "Visibility conventions",
        "targetacq.physics.atmosphere.VISIBILITY_CONVENTIONS",
        ("name", "−ln(contrast threshold)"),
        rows,
        _attr_doc("targetacq.physics.atmosphere", "VISIBILITY_CONVENTIONS"),
    )


def _path_models() -> RegistryTable:
    from targetacq.physics.named_atmospheres import PATH_MODELS

    rows = tuple(
        (name, ", ".join(entry.settings), entry.source) for name, entry in PATH_MODELS.items()
    )
    return RegistryTable(
        "path_models",
        "Path models",
        "targetacq.physics.named_atmospheres.PATH_MODELS",
        ("name", "settings", "source"),
        rows,
        _attr_doc("targetacq.physics.named_atmospheres", "PATH_MODELS"),
    )


def _named_aerosols() -> RegistryTable:
    from targetacq.base.tables import load_table
    from targetacq.physics.named_atmospheres import AEROSOLS, DEFAULT_VISIBILITY

    table = load_table("named_atmospheres")
    visibilities: dict[str, list[float]] = {}
    for aerosol, vis in zip(table.column("aerosol"), table.numbers("visibility_km"), strict=True):
        visibilities.setdefault(aerosol, [])
        if vis not in visibilities[aerosol]:
            visibilities[aerosol].append(vis)
    rows = []
    for name in AEROSOLS:
        default = DEFAULT_VISIBILITY[name]
        grid = sorted(visibilities[name])
        rows.append(
            (
                name,
                "–" if default is None else f"{default / 1e3:g}",
                "–" if grid == [0.0] else ", ".join(f"{v:g}" for v in grid),
                "data/named_atmospheres.csv",
            )
        )
    return RegistryTable(
        "named_aerosols",
        "Aerosols of the named atmospheres",
        "targetacq.physics.named_atmospheres.AEROSOLS",
        ("name", "default visibility [km]", "table visibilities [km]", "source"),
        tuple(rows),
        _attr_doc("targetacq.physics.named_atmospheres", "AEROSOLS")
        + " Model atmospheres: "
        + ", ".join(_named_atmospheres())
        + ".",
    )


def _named_atmospheres() -> tuple[str, ...]:
    from targetacq.physics.named_atmospheres import ATMOSPHERES

    return ATMOSPHERES


def _bands() -> RegistryTable:
    from targetacq.base.tables import load_table
    from targetacq.physics.bands import BANDS

    table = load_table("bands")
    labels = dict(zip(table.column("band"), table.column("label"), strict=True))
    rows = tuple(
        (name, f"{low * 1e6:g}–{high * 1e6:g}", labels.get(name, ""), "data/bands.csv")
        for name, (low, high) in BANDS.items()
    )
    return RegistryTable(
        "bands",
        "Spectral bands",
        "targetacq.physics.bands.BANDS",
        ("name", "limits [µm]", "label", "source"),
        rows,
        _attr_doc("targetacq.physics.bands", "BANDS")
        + " Source: "
        + " ".join(table.provenance.split()),
    )


def _motion_rules() -> RegistryTable:
    from targetacq.acquisition.probabilities import MOTION_RULES

    rows = tuple((name, rule.source) for name, rule in MOTION_RULES.items())
    return RegistryTable(
        "motion_rules",
        "Motion rules",
        "targetacq.acquisition.probabilities.MOTION_RULES",
        ("name", "what it is and its source"),
        rows,
        _attr_doc("targetacq.acquisition.probabilities", "MOTION_RULES"),
    )


def _semantics() -> RegistryTable:
    from targetacq.acquisition.probabilities import ACQUISITION_SEMANTICS

    rows = tuple((name, s.source) for name, s in ACQUISITION_SEMANTICS.items())
    return RegistryTable(
        "acquisition_semantics",
        "Acquisition semantics",
        "targetacq.acquisition.probabilities.ACQUISITION_SEMANTICS",
        ("name", "what it is and its source"),
        rows,
        _attr_doc("targetacq.acquisition.probabilities", "ACQUISITION_SEMANTICS"),
    )


def _redraw_rules() -> RegistryTable:
    from targetacq.acquisition.engagement import REDRAW_RULES

    rows = tuple((name, f"{r.description} ({r.source})") for name, r in REDRAW_RULES.items())
    return RegistryTable(
        "redraw_rules",
        "Redraw rules of the step API and simulate",
        "targetacq.acquisition.engagement.REDRAW_RULES",
        ("name", "what it is and its source"),
        rows,
        _attr_doc("targetacq.acquisition.engagement", "REDRAW_RULES"),
    )


def _projections() -> RegistryTable:
    from targetacq.physics.optics import FIELD_OF_VIEW_PROJECTIONS

    rows = tuple((name, text) for name, text in FIELD_OF_VIEW_PROJECTIONS.items())
    return RegistryTable(
        "fov_projections",
        "Field-of-view projections",
        "targetacq.physics.optics.FIELD_OF_VIEW_PROJECTIONS",
        ("name", "what it is and its source"),
        rows,
        _attr_doc("targetacq.physics.optics", "FIELD_OF_VIEW_PROJECTIONS"),
    )


def _targets() -> RegistryTable:
    from targetacq.physics.targets import TARGETS

    sources = {t.source for t in TARGETS.values()}
    shared = len(sources) == 1
    rows = tuple(
        (
            name,
            _number(t.critical_dimension),
            f"{_number(t.height)} × {_number(t.width)}",
            t.description,
            *(() if shared else (t.source,)),
        )
        for name, t in TARGETS.items()
    )
    intro = _attr_doc("targetacq.physics.targets", "TARGETS")
    if shared:
        intro += " Source: " + _cell(next(iter(sources)))
    return RegistryTable(
        "targets",
        "Named targets",
        "targetacq.physics.targets.TARGETS",
        (
            "name",
            "critical dimension [m]",
            "outline height × width [m]",
            "what it is",
            *(() if shared else ("source",)),
        ),
        rows,
        intro,
    )


def _clutter_regions() -> RegistryTable:
    from targetacq.acquisition.transforms import CLUTTER_REGIONS
    from targetacq.base.tables import load_table

    table = load_table("schmieder_weathersby")
    p = [float(v) for v in table.column("probability")]
    rows = tuple(
        (region, _number(table.numbers(region)[p.index(0.5)]), "data/schmieder_weathersby.csv")
        for region in CLUTTER_REGIONS
    )
    return RegistryTable(
        "clutter_regions",
        "Clutter regions",
        "targetacq.acquisition.transforms.CLUTTER_REGIONS",
        ("name", "N50 of detection [cycles]", "source"),
        rows,
        _attr_doc("targetacq.acquisition.transforms", "CLUTTER_REGIONS")
        + " Source: "
        + " ".join(table.provenance.split()),
    )


def _plausible_ranges() -> RegistryTable:
    from targetacq.scenario.plausibility import PLAUSIBLE_RANGES

    rows = tuple(
        (
            ", ".join(row.locations),
            f"{'≥' if row.side == 'above' else '≤'} {row.limit}",
            row.question,
            row.reason,
        )
        for row in PLAUSIBLE_RANGES
    )
    return RegistryTable(
        "plausible_ranges",
        "Plausibility warnings",
        "targetacq.scenario.plausibility.PLAUSIBLE_RANGES",
        ("where", "warns at", "likely slip", "why no real sensor or scene reaches it"),
        rows,
        _attr_doc("targetacq.scenario.plausibility", "PLAUSIBLE_RANGES")
        + " A value beyond its limit is valid and runs as given; validating the scenario warns "
        "with the value's location and its likely fix "
        "(targetacq.scenario.plausibility.PlausibilityWarning"
        "; the command line prints one line per warning on stderr, the web API answers them in "
        '"warnings").',
    )


_GENERATORS: tuple[Callable[[], RegistryTable], ...] = (
    _criteria,
    _transforms,
    _noise_models,
    _snr_laws,
    _sensor_types,
    _targets,
    _bands,
    _obscurants,
    _levels,
    _visibility,
    _path_models,
    _named_aerosols,
    _clutter_regions,
    _motion_rules,
    _semantics,
    _redraw_rules,
    _projections,
    _plausible_ranges,
)


@functools.cache
def registries() -> tuple[RegistryTable, ...]:
    """Every rendered registry, one :class:`RegistryTable` each, in the order of the page."""
    return tuple(make() for make in _GENERATORS)


def _cell(text: Any) -> str:
    """Plain text as one table cell: one line, with the characters that start markup escaped."""
    text = " ".join(str(text).split())
    for char in ("\\", "*", "`", "|", "_"):
        text = text.replace(char, "\\" + char)
    return text


def _rest(text: str) -> str:
    """reStructuredText (a docstring) as one line."""
    return " ".join(text.split())


def render(table: RegistryTable) -> str:
    """The reStructuredText of one registry: a section with its intro and a list-table."""
    lines = [table.title, "-" * len(table.title), ""]
    lines.append(f"Rendered from ``{table.origin}`` ({len(table.rows)} entries).")
    if table.intro:
        lines += ["", _rest(table.intro)]
    lines += ["", ".. list-table::", "   :header-rows: 1", "   :class: registry", ""]
    for row in (table.header, *table.rows):
        lines.append(f"   * - {_cell(row[0]) if row is table.header else '``' + row[0] + '``'}")
        lines += [f"     - {_cell(cell)}" for cell in row[1:]]
    return "\n".join(lines) + "\n"


def write_tables(outdir: Path) -> list[Path]:
    """Write ``<stem>.rst.inc`` per registry into ``outdir``, only where the text changed."""
    written = []
    for table in registries():
        path = outdir / f"{table.stem}.rst.inc"
        _write(path, render(table))
        written.append(path)
    return written


def _api_summary() -> str:
    """The top-level names of ``targetacq.__all__`` with links to where they are documented."""
    import targetacq

    lines = [".. list-table::", "   :header-rows: 1", "", "   * - name", "     - summary"]
    for name in targetacq.__all__:
        obj = getattr(targetacq, name)
        module = getattr(obj, "__module__", None)
        if callable(obj) and module and module.startswith("targetacq"):
            role = "class" if isinstance(obj, type) else "func"
            ref = f":{role}:`~{module}.{name}`"
            summary = _first_line(obj.__doc__ or "")
        else:
            source = _owner_module(name)
            ref = f":data:`~{source}.{name}`"
            summary = _attr_doc(source, name)
        lines += [f"   * - {ref}", f"     - {_rest(summary)}"]
    return "\n".join(lines) + "\n"


def _owner_module(name: str) -> str:
    """The module that defines a name the package re-exports (its table of re-exports)."""
    import targetacq

    module = f"targetacq.{targetacq._MODULE_OF[name]}"
    if not _attr_doc(module, name):
        raise LookupError(f"{module} does not document {name!r}")
    return module


def _write(path: Path, text: str) -> None:
    # Rewriting an unchanged file would make Sphinx re-read every page that includes it.
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


REEXPORTING = ("targetacq", "targetacq.core")
"""Packages that only re-export: their members are documented in the modules that define them."""


def module_page(module: str) -> str:
    """The API page of one module: its docstring and members (autodoc with numpydoc)."""
    title = f"``{module}``"
    text = f"{title}\n{'=' * len(title)}\n\n.. automodule:: {module}\n"
    if module in REEXPORTING:
        text += "   :no-members:\n"
    return text


def write_pages(generated: Path, modules: list[str]) -> None:
    """Write everything this extension generates under ``generated`` (``docs/generated``): the
    registry tables, one API page per module of ``modules``, their table of contents and the
    summary of the package's names."""
    tables = write_tables(generated / "registries")
    _write(
        generated / "registries" / "all.rst.inc",
        "".join(f".. include:: /generated/registries/{path.name}\n" for path in tables),
    )
    for module in modules:
        _write(generated / "api" / f"{module}.rst", module_page(module))
    _write(
        generated / "api_modules.rst.inc",
        ".. toctree::\n   :maxdepth: 1\n\n"
        + "".join(f"   /generated/api/{module}\n" for module in modules),
    )
    _write(generated / "api_summary.rst.inc", _api_summary())


def _on_builder_inited(app: Any) -> None:
    write_pages(Path(app.srcdir) / "generated", list(app.config.api_modules))


def setup(app: Any) -> dict[str, Any]:
    """Sphinx entry point."""
    app.add_config_value("api_modules", [], "env")
    app.connect("builder-inited", _on_builder_inited)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
