"""The `plot` and `report` commands: figures and the HTML report."""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Mapping, Sequence
from typing import Annotated, Any

import typer

from targetacq import __version__, ranges
from targetacq.atmosphere import (
    EXTINCTION_LEVELS,
)
from targetacq.bands import BANDS
from targetacq.cli import (
    app,
)
from targetacq.cli.options import range_case_options
from targetacq.core.cases import RangeCase
from targetacq.criteria import CRITERIA, get_criterion
from targetacq.model import ModelChain
from targetacq.noise import NOISE_MODELS
from targetacq.outputs import output_path
from targetacq.scenario import load_scenario
from targetacq.services.options import option_product, typed_options
from targetacq.services.range_case import (
    RangeSetup,
    option_band,
    option_choice,
    option_criterion,
    option_probabilities,
    option_quantity,
    range_setup,
)
from targetacq.transforms import TRANSFORMS

# targetacq.plots and targetacq.report (matplotlib, about 0.3 s) are imported by the commands
# that draw, not when the CLI starts.

PLOT_KIND_NAMES = ("curves", "transforms", "atmosphere")
"""The names of :data:`targetacq.plots.PLOT_KINDS`, known without importing matplotlib (for the
help text; a test keeps the two equal)."""

_REPORT_PROBABILITIES = "0.5,0.8,0.95"
"""The probabilities of a figure's or a report's DRI points unless --probability is given."""


def _given(case_options: dict[str, Any]) -> set[str]:
    """The names of the range-case options given on the command line."""
    return {name for name, value in case_options.items() if value not in (None, False)}


def _check_scenario_options(case_options: dict[str, Any], command: str, takes: str) -> None:
    """A command given a scenario file takes its sensors and targets from the file: any other
    range-case option than --probability is a ``ValueError`` naming the options it got."""
    unused = _given(case_options) - {"probability"}
    if unused:
        flags = ", ".join("--" + name.replace("_", "-") for name in sorted(unused))
        raise ValueError(
            f"{command} takes its sensors and targets from the file; it takes {takes} only, "
            f"got {flags}"
        )


def _sources() -> str:
    """The model's source as a report prints it: the thesis, and where our errata and
    assumptions are written down (targetacq.report, with matplotlib, is imported on use)."""
    from targetacq.report import THESIS_CITATION

    return f"{THESIS_CITATION}; errata and assumptions: see the targetacq user guide"


_FLOOR = 0.02
"""Automatic range axes extend until every task's probability is below this."""

_MAX_AUTO_RANGE = 500e3
"""The longest automatic range axis [m]; the caption says where curves stop above the floor."""

_SIMULATION_RUNS, _SIMULATION_SEED, _SIMULATION_STEPS = 500, 0, 240
"""Runs, seed and least number of time steps of a scenario report's simulated first times."""


def _titled(heading: str, conditions: str) -> str:
    """A figure title: the heading, then the conditions wrapped to the figure's width."""
    return "\n".join([heading, textwrap.fill(conditions, 100)])


def _sensor_text(setup: RangeSetup) -> str:
    sensor = setup.sensor
    if "pitch_m" in sensor:
        pitch_um, focal_mm = sensor["pitch_m"] * 1e6, sensor["focal_length_m"] * 1e3
        optics_text = f"{pitch_um:.3g} µm pitch, {focal_mm:.4g} mm focal length"
    elif "hfov_rad" in sensor:
        optics_text = f"{math.degrees(sensor['hfov_rad']):.3g}° over {sensor['pixels']:.0f} pixels"
    else:
        optics_text = "IFOV given"
    return f"IFOV {setup.case.ifov * 1e3:.4g} mrad ({optics_text})"


def _title(setup: RangeSetup) -> str:
    return (
        f"{_sensor_text(setup)} — target critical dimension {setup.case.critical_dimension:.3g} m"
    )


def _field_of_view(setup: RangeSetup) -> str:
    """The field of view where the pixels are known, else the IFOV."""
    sensor = setup.sensor
    if "hfov_rad" in sensor:
        return (
            f"HFOV {math.degrees(sensor['hfov_rad']):.4g}° over {sensor['pixels']:.0f} pixels "
            f"(IFOV {setup.case.ifov * 1e3:.4g} mrad; the vertical field needs the rows, not "
            "given)"
        )
    return (
        f"IFOV {setup.case.ifov * 1e3:.4g} mrad per pixel (no pixel count given, so no field "
        "of view: give --hfov and --pixels)"
    )


def _conditions(setup: RangeSetup) -> dict[str, str]:
    """Weather, clutter and criterion of a case, for titles."""
    case = setup.case
    if setup.path:
        weather = f"{setup.path['source']} ({setup.path['extinction_np_per_km']:.3g} Np/km)"
    else:
        weather = "no atmosphere"
    if case.region is not None:
        clutter = f"{case.region} clutter"
    elif case.scr is not None:
        clutter = f"SCR {float(case.scr):.3g}"
    else:
        clutter = "no clutter"
    return {"weather": weather, "clutter": clutter, "criterion": setup.criterion.name}


def _shared_conditions(conditions: Sequence[Mapping[str, str]]) -> str:
    """The conditions of all cases in one line: a value where they agree, each case's where
    not."""
    parts = []
    for key in ("weather", "clutter", "criterion"):
        values = list(dict.fromkeys(c[key] for c in conditions))
        text = values[0] if len(values) == 1 else "per case: " + " / ".join(values)
        parts.append(text if key == "clutter" else f"{key} {text}")
    return "; ".join(parts)


def _spaced(text: str) -> str:
    """ "0.75m" → "0.75 m": a typed quantity with a space before its unit."""
    found = re.fullmatch(r"\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*([^\d\s].*)", text)
    return f"{found.group(1)} {found.group(2)}" if found else text


def _case_label(swept: Mapping[str, Any]) -> str:
    """A case's label from its swept option values: "critical dimension 0.75 m, fog:low"."""
    parts = []
    for name, value in swept.items():
        text = str(value)
        if name == "obscurant":
            parts.append("no obscurant" if text == "none" else text)
        else:
            parts.append(f"{name.replace('_', ' ')} {_spaced(text)}")
    return ", ".join(parts)


def _performance(
    cases: Mapping[str, RangeCase],
    max_range: str | float | None,
    probabilities: Sequence[float],
    requirement: tuple[float, float | None] | None = None,
) -> tuple[Any, str]:
    """Range performance of the cases on 600 ranges, and a caption saying where they stop.

    The range axis goes out to --max-range (text, or a number of metres); by default to a
    quarter beyond the farthest DRI range of the table (and the requirement's range), so that
    every answer is on the chart and none is squeezed into its first few per cent; where no
    DRI range is finite, to where every task of every case is below :data:`_FLOOR` (bounded by
    :data:`_MAX_AUTO_RANGE` either way).
    """
    answers = [
        float(r)
        for case in cases.values()
        for p in probabilities
        for r in ranges.case_ranges(case, p).values()
    ]
    answers = [r for r in answers if math.isfinite(r) and r > 0]
    if requirement is not None:
        answers.append(requirement[0])
    if isinstance(max_range, float):
        r_max = max_range
        limit = "twice the requirement's range"
    elif max_range is not None:
        r_max = option_quantity(max_range, "length", "--max-range")
        limit = f"--max-range {max_range}"
    elif answers:
        r_max = min(1.25 * max(answers), _MAX_AUTO_RANGE)
        limit = "a quarter beyond the farthest DRI range of the table"
    else:
        reach = [
            float(r)
            for case in cases.values()
            for p in (_FLOOR, min(probabilities))
            for r in ranges.case_ranges(case, p).values()
        ]
        finite = [r for r in reach if math.isfinite(r) and r > 0]
        r_max = min(1.05 * max(finite), _MAX_AUTO_RANGE) if finite else 10e3
        limit = f"the automatic limit of {_MAX_AUTO_RANGE / 1e3:g} km"
    grid = [r_max * (k + 1) / 600 for k in range(600)]
    performance = ranges.range_performance(grid, cases, probabilities)
    note = _stop_note(performance, r_max, limit)
    if requirement is not None:
        p_text = "" if requirement[1] is None else f"P ≥ {requirement[1]:g} "
        note += f" Star and dashed line: the requirement, {p_text}at {requirement[0]:,.0f} m."
    return performance, note + " Dots: the DRI ranges of the table."


def _stop_note(performance: Any, r_max: float, limit: str) -> str:
    """Where the curves stop and why, naming the pairs still at or above :data:`_FLOOR`."""
    last = performance.curves.isel(range=-1)
    above = [
        f"P({task}) {float(last[task].sel(case=case)):.2f} for {case}"
        for task in ("detection", "recognition", "identification")
        if task in last
        for case in [str(c) for c in last["case"].values]
        if float(last[task].sel(case=case)) >= _FLOOR
    ]
    if above:
        return (
            f"The curves stop at {r_max / 1e3:.4g} km ({limit}), where "
            + ", ".join(above[:6])
            + (" and more" if len(above) > 6 else "")
            + f" (still at or above {_FLOOR:.0%})."
        )
    return (
        f"The curves are drawn out to {r_max / 1e3:.4g} km, where every task's probability "
        f"is below {_FLOOR:.0%}."
    )


def option_requirement(text: str | None) -> tuple[float, float | None] | None:
    """``--requirement RANGE[,P]``: the range [m] and, optionally, the probability a task must
    reach there."""
    if text is None:
        return None
    parts = [part.strip() for part in text.split(",")]
    if len(parts) > 2 or not parts[0]:
        raise ValueError(
            f"--requirement takes a range and optionally a probability, e.g. 1km,0.8; got {text!r}"
        )
    r = option_quantity(parts[0], "length", "--requirement")
    if not (r > 0 and math.isfinite(r)):
        raise ValueError(f"--requirement range must be > 0 and finite; got {parts[0]!r}")
    if len(parts) == 1:
        return r, None
    try:
        p = float(parts[1])
    except ValueError:
        raise ValueError(f"--requirement probability must be a number; got {parts[1]!r}") from None
    if not 0 < p < 1:
        raise ValueError(f"--requirement probability must be in (0, 1); got {parts[1]!r}")
    return r, p


def _atmosphere_figures(
    bands: Sequence[tuple[float, float]], r_max: float, level: str, conditions: str
) -> dict[str, Any]:
    """One Table 7.1 figure per band in use, headed by the band."""
    from targetacq.bands import band_name
    from targetacq.plots import plot_atmosphere

    figures = {}
    for band in dict.fromkeys(bands):
        try:
            name = band_name(band)
        except ValueError:  # Table 7.1 has the named bands only
            continue
        figures[f"Atmosphere, {name} band"] = plot_atmosphere(
            band,
            r_max,
            level,
            title=_titled(
                f"Atmosphere, Table 7.1 {level} extinction, {name} band "
                f"({band[0] * 1e6:g}–{band[1] * 1e6:g} µm)",
                f"this report: {conditions}",
            ),
        )
    return figures


@app.command()
@range_case_options
def plot(
    kind: Annotated[str, typer.Argument(help=f"Figure: {', '.join(PLOT_KIND_NAMES)}.")],
    out: Annotated[str, typer.Option(help="Output file, .png or .svg.")],
    max_range: Annotated[
        str | None, typer.Option(help="Largest range on the axis, e.g. 8km (default: automatic).")
    ] = None,
    level: Annotated[
        str | None,
        typer.Option(help="atmosphere: Table 7.1 level, low|nominal|high (default nominal)."),
    ] = None,
    title: Annotated[str | None, typer.Option(help="Figure title.")] = None,
    *,
    case_options: dict[str, Any],
) -> None:
    """Draw a figure. `curves` takes every sensor, target and path option of `targetacq dri`
    (and --probability for the marked DRI points); `transforms` takes --criterion or --n50;
    `atmosphere` takes --band.

    Example: targetacq plot curves --example --out curves.png
    """
    from targetacq.plots import (
        FIGURE_FORMATS,
        PLOT_KINDS,
        plot_atmosphere,
        plot_range_performance,
        plot_transforms,
        save_figure,
    )

    option_choice(kind, PLOT_KINDS, "plot kind")
    output_path(out, FIGURE_FORMATS, "figure file")  # before any work
    params, given = typed_options(case_options, "plot"), _given(case_options)
    allowed = {
        "curves": None,
        "transforms": {"criterion", "n50"},
        "atmosphere": {"band"},
    }[kind]
    if allowed is not None and given - allowed:
        unused = ", ".join("--" + name.replace("_", "-") for name in sorted(given - allowed))
        raise ValueError(f"plot {kind} does not use {unused}")
    if level is not None and kind != "atmosphere":
        raise ValueError(f"plot {kind} does not use --level (plot atmosphere does)")
    if max_range is not None and kind == "transforms":
        raise ValueError("plot transforms does not use --max-range (its axis is cycles)")
    if kind == "curves":
        setup = range_setup(**params, default_probability=_REPORT_PROBABILITIES)
        if not setup.criterion.gives_probabilities:
            raise ValueError(
                f"plot curves needs a criterion with probabilities (not {setup.criterion.name})"
            )
        performance, _ = _performance({"this sensor": setup.case}, max_range, setup.probabilities)
        conditions = _shared_conditions([_conditions(setup)])
        fig = plot_range_performance(performance, title=title or _titled(_title(setup), conditions))
    elif kind == "transforms":
        crit = (
            option_criterion(params["n50"])
            if params["n50"]
            else get_criterion(
                option_choice(
                    "johnson" if params["criterion"] is None else params["criterion"],
                    CRITERIA,
                    "--criterion",
                )
            )
        )
        fig = plot_transforms(crit, title=title)
    else:
        r_max = 10e3 if max_range is None else option_quantity(max_range, "length", "--max-range")
        level = option_choice(level or "nominal", EXTINCTION_LEVELS, "--level")
        band_value = option_band(params["band"]) if params["band"] else BANDS["lwir"]
        fig = plot_atmosphere(band_value, r_max, level, title=title)
    written = save_figure(fig, out)
    typer.echo(f"wrote {written}")


@app.command()
@range_case_options
def report(
    scenario: Annotated[
        str | None,
        typer.Argument(help="A scenario file: every sensor-target pair becomes a case."),
    ] = None,
    *,
    out: Annotated[str, typer.Option(help="Output file, .html or .pdf (PDF needs Chromium).")],
    max_range: Annotated[
        str | None,
        typer.Option(
            help="Largest range of the curves, e.g. 8km (default: a quarter beyond the farthest "
            "DRI range)."
        ),
    ] = None,
    title: Annotated[str | None, typer.Option(help="Report title.")] = None,
    requirement: Annotated[
        str | None,
        typer.Option(
            help="A range and optionally the probability a task must reach there, e.g. "
            "1km,0.8: marked on the range chart, with a second chart zoomed on it."
        ),
    ] = None,
    case_options: dict[str, Any],
) -> None:
    """Write a self-contained report (HTML, or PDF printed by headless Chromium): inputs, model
    choices with sources, the DRI table (at --probability, default 50 / 80 / 95 %) and the
    figures. Give a scenario file (every sensor-target pair becomes a case; takes
    --probability, --max-range and --title), or the sensor, target and path options of
    `targetacq dri`, where any option may take a list (`--critical-dimension 0.75m,2.3m
    --obscurant haze,fog:low`): one case per combination, all in one table and on shared
    figures.

    Example: targetacq report --example --critical-dimension 0.75m,2.3m --out r.html
    """
    from targetacq.report import REPORT_FORMATS, render_report, require_browser, write_report

    _, kind = output_path(out, REPORT_FORMATS, "the report file")  # before any work
    wanted = option_requirement(requirement)
    if kind == "pdf":
        require_browser()
    if scenario is not None:
        _check_scenario_options(
            case_options, "a scenario report", "--probability, --max-range and --title"
        )
        probability = case_options.get("probability") or _REPORT_PROBABILITIES
        parts = _scenario_report(scenario, max_range, title, option_probabilities(probability))
    else:
        parts = _range_case_report(case_options, max_range, title, wanted)
    heading, performance, sections, figures, captions = parts
    page = render_report(
        performance, sections, figures, title=heading, version=__version__, captions=captions
    )
    typer.echo(f"wrote {write_report(out, page)}")


def _range_case_report(
    case_options: dict[str, Any],
    max_range: str | None,
    title: str | None,
    requirement: tuple[float, float | None] | None = None,
) -> tuple[Any, ...]:
    """Heading, range performance, sections, figures and captions of a report of range cases:
    one case per combination of the options given as lists."""
    from targetacq.plots import plot_range_performance, plot_transforms

    setups: dict[str, RangeSetup] = {}
    bands: list[tuple[float, float]] = []
    swept_names: list[str] = []
    for swept, options in option_product(case_options):
        setup = range_setup(**options, default_probability=_REPORT_PROBABILITIES)
        if not setup.criterion.gives_probabilities:
            raise ValueError(
                f"the report needs a criterion with probabilities (not {setup.criterion.name})"
            )
        setups[_case_label(swept) or "this sensor"] = setup
        swept_names = list(swept)
        if setup.path and options.get("band"):
            bands.append(option_band(options["band"]))
    first = next(iter(setups.values()))
    probabilities = first.probabilities
    cases = {label: s.case for label, s in setups.items()}
    performance, note = _performance(cases, max_range, probabilities, requirement)
    conditions = _shared_conditions([_conditions(s) for s in setups.values()])
    if title:
        heading = title
    elif len(setups) == 1:
        heading = _title(first)
    else:
        sensors = {_sensor_text(s) for s in setups.values()}
        sensor = sensors.pop() if len(sensors) == 1 else "several sensors"
        heading = f"{sensor} — {len(setups)} cases over " + ", ".join(
            name.replace("_", " ") for name in swept_names
        )
    captions = {"Range performance": note}
    figures = {
        "Range performance": plot_range_performance(
            performance, title=_titled(heading, conditions), requirement=requirement
        )
    }
    if requirement is not None:
        near, near_note = _performance(cases, 2.0 * requirement[0], probabilities, requirement)
        figures["Range performance near the requirement"] = plot_range_performance(
            near, title=_titled(heading, conditions), requirement=requirement
        )
        captions["Range performance near the requirement"] = near_note
    criteria = {s.criterion.name: s.criterion for s in setups.values()}
    for name, crit in criteria.items():
        key = "Transforms" if len(criteria) == 1 else f"Transforms, criterion {name}"
        figures[key] = plot_transforms(
            crit,
            title=_titled(f"Resolution-to-probability transforms (criterion {name})", conditions),
        )
    r_max = float(performance.curves["range"].values[-1])
    levels = {
        s.path["source"].split(", ")[1]
        for s in setups.values()
        if s.path.get("source", "").startswith("Table 7.1")
    }
    level = levels.pop() if len(levels) == 1 else "nominal"
    figures.update(_atmosphere_figures(bands, r_max, level, conditions))
    # What differs from case to case gets a column per case in each section (one table, no
    # cell that strings several cases' values together).
    sections = _merged_sections({label: _report_sections(s) for label, s in setups.items()})
    return heading, performance, sections, figures, captions


def _merged_sections(
    per_case: Mapping[str, Mapping[str, Mapping[str, str]]],
) -> dict[str, dict[str, Any]]:
    """The sections of several cases as one: an item's value where the cases agree, else a
    mapping case → value (a column per case in the report)."""
    merged: dict[str, dict[str, Any]] = {}
    for sections in per_case.values():
        for heading, items in sections.items():
            for item in items:
                merged.setdefault(heading, {})[item] = ""
    for heading, items in merged.items():
        for item in items:
            values = {
                label: sections.get(heading, {}).get(item, "—")
                for label, sections in per_case.items()
            }
            distinct = set(values.values())
            items[item] = distinct.pop() if len(distinct) == 1 else values
    return merged


def _scenario_performance(
    chain: Any, max_range: str | None, probabilities: list[float], axis: bool = True
) -> tuple[Any, str]:
    """Range performance of every sensor-target pair of a scenario, any sensor type, through
    the core (:func:`targetacq.core.pair_ranges.pair_performance`), and a caption saying where
    the curves stop.

    The range axis goes out to --max-range; by default (with ``axis``) to a quarter beyond the
    farthest DRI range, as the analyst's curves have it (a second pass of the core on that
    grid), else to where every task of every pair is below 0.02 (1, 2, 4, … km).
    """
    from targetacq.core.pair_ranges import pair_performance

    rows = list(range(len(chain.compiled.scene.sensors.names)))
    how = (
        " Every pair through the core, each target moved away from the sensor along its start "
        "bearing. Dots: the DRI ranges of the table."
    )
    if max_range is not None:
        r_max = option_quantity(max_range, "length", "--max-range")
        performance = pair_performance(chain, rows, probabilities, max_range=r_max)
        return performance, _stop_note(performance, r_max, f"--max-range {max_range}") + how
    performance = pair_performance(chain, rows, probabilities, limit=_MAX_AUTO_RANGE)
    found = [float(r) for r in performance.dri["range_m"] if math.isfinite(r) and r > 0]
    if axis and found:
        r_max = min(1.25 * max(found), _MAX_AUTO_RANGE)
        performance = pair_performance(chain, rows, probabilities, max_range=r_max)
        limit = "a quarter beyond the farthest DRI range of the table"
        return performance, _stop_note(performance, r_max, limit) + how
    r_max = float(performance.curves["range"].values[-1])
    return performance, _stop_note(performance, r_max, "the automatic limit") + how


def _scenario_report(
    path: str, max_range: str | None, title: str | None, probabilities: list[float]
) -> tuple[Any, ...]:
    """Heading, range performance, sections, figures and captions of a scenario's report."""
    from targetacq.plots import (
        plot_first_times,
        plot_range_performance,
        plot_timeline,
        plot_transforms,
    )
    from targetacq.search import simulate
    from targetacq.sensors import get_sensor_type

    scenario = load_scenario(path)
    chain = ModelChain(scenario)
    performance, note = _scenario_performance(chain, max_range, probabilities)
    heading = title or (scenario.name or path)
    model = scenario.model
    atm = scenario.atmosphere
    criteria = list(dict.fromkeys(c.name for c in chain.criteria))
    conditions = (
        f"weather {_atmosphere_text(atm)}; clutter {_clutter_text(scenario.background)}; "
        f"criterion {', '.join(criteria)}"
    )
    sensors = {}
    for s in scenario.sensors:
        if s.radar is not None:
            r = s.radar
            sensors[s.name] = (
                f"radar, {r.frequency / 1e9:.4g} GHz, peak power {r.power:g} W, beamwidth "
                f"{math.degrees(r.beamwidth):.3g}°, pulse {r.pulse_length * 1e6:.3g} µs, "
                f"P_fa {r.false_alarm:g}, detector {r.detector}"
            )
            continue
        fov = s.field_of_view
        field = (
            f"HFOV × VFOV {math.degrees(fov[0]):.3g}° × {math.degrees(fov[1]):.3g}° "
            f"({s.pixels[0]} × {s.pixels[1]} pixels)"
            if fov is not None and s.pixels is not None
            else "field of view: no pixel count given"
        )
        sensors[s.name] = (
            f"{s.type}, band {s.limits[0] * 1e6:g}–{s.limits[1] * 1e6:g} µm, IFOV "
            f"{s.pixel_ifov * 1e3:.4g} mrad, {field}"
            + (f", aperture {s.aperture * 1e3:g} mm" if s.aperture else "")
        )
    targets = {
        t.name: f"{' × '.join(f'{d:g}' for d in t.dimensions)} m, criterion "
        f"{chain.criteria[g].name}"
        + (f", {t.temperature:g} K" if t.temperature is not None else "")
        + (", moving" if t.moving else "")
        + (", hot spot" if t.hot_spot else "")
        for g, t in enumerate(scenario.targets)
    }
    scene = chain.compiled.scene
    seen = chain.compute([scenario.time.start])["critical_dimension"][..., 0]
    case_items = {
        f"{sensor} → {target}": f"critical dimension {seen[s, g]:.3g} m at the start, IFOV "
        f"{scene.sensors.ifov[s] * 1e3:.4g} mrad, criterion {chain.criteria[g].name}"
        for s, sensor in enumerate(scene.sensors.names)
        if get_sensor_type(scene.sensors.types[s]).kind == "imaging"
        for g, target in enumerate(scene.targets.names)
    }
    sections = {
        "Scenario": {
            "file": path,
            "name": scenario.name or "(unnamed)",
            "cases": "every sensor–target pair through the core, each target moved away from "
            "the sensor along its start bearing (its outline seen from each range)",
        },
        "Sensors": sensors,
        "Targets": targets,
        "Cases": case_items,
        "Background and path": {
            "clutter": _clutter_text(scenario.background),
            "atmosphere": _atmosphere_text(atm),
            "noise": "SNR = 20 log10(τ/(1−τ)) dB, Eqs. (7.5)–(7.7); noise model "
            f"{model.noise_model}: {NOISE_MODELS[model.noise_model].source}",
        },
        "Model choices and sources": {
            "transform": f"{model.transform}: {TRANSFORMS[model.transform].source}",
            "criteria": "; ".join(dict.fromkeys(f"{c.name} ({c.source})" for c in chain.criteria)),
            "fusion": "sensor level, P = 1 − Π(1 − P_s) over the sensors (Eq. (8.4))",
            "ordering": "P_id <= P_rec <= P_det: nothing is recognised that was not detected",
            "sources": _sources(),
        },
    }
    figures = {
        "Range performance": plot_range_performance(
            performance,
            title=_titled(f"{heading}: range performance per sensor–target pair", conditions),
        )
    }
    captions = {"Range performance": note}
    figures["Transforms"] = plot_transforms(
        scenario.model.criterion,
        title=_titled(
            f"Resolution-to-probability transforms (criterion {scenario.model.criterion})",
            conditions,
        ),
    )
    if atm.obscurant is not None or atm.extinction is not None or atm.visibility is not None:
        _, _, level = (atm.obscurant or "").partition(":")
        r_max = float(performance.curves["range"].values[-1])
        figures.update(
            _atmosphere_figures(
                [s.limits for s in scenario.sensors if s.radar is None],
                r_max,
                level or "nominal",
                conditions,
            )
        )
    dataset = chain.evaluate().dataset
    several = len(chain.sensor_names) > 1
    figures["Timeline"] = plot_timeline(
        dataset,
        title=_titled(
            f"{heading}: probabilities over time, per sensor"
            + (" and fused (Eq. (8.4))" if several else ""),
            conditions,
        ),
    )
    grid = scenario.time
    duration = float(grid.stop - grid.start)
    captions["Timeline"] = (
        f"Each target's probabilities at the scenario's times ({grid.start:g} s to {grid.stop:g} s "
        f"every {grid.step:g} s)"
        + (
            "; thin broken lines per sensor, thick solid lines fused over the sensors."
            if several
            else "."
        )
    )
    if duration > 0:
        step = min(float(grid.step), duration / _SIMULATION_STEPS)
        result = simulate(
            chain,
            duration=duration,
            step=step,
            runs=_SIMULATION_RUNS,
            seed=_SIMULATION_SEED,
        )
        figures["Simulated first times"] = plot_first_times(
            result,
            title=_titled(
                f"{heading}: first times over {_SIMULATION_RUNS} simulated runs "
                f"(seed {_SIMULATION_SEED})" + (", fused over the sensors" if several else ""),
                conditions,
            ),
        )
        captions["Simulated first times"] = (
            f"Share of {_SIMULATION_RUNS} runs (targetacq simulate, seed {_SIMULATION_SEED}, "
            f"step {step:.3g} s) that have detected, recognised and identified each target by "
            "each time; a curve ending below 1 means some runs never got there in the "
            f"{duration:g} s simulated."
        )
    return heading, performance, sections, figures, captions


def _clutter_text(background: Any) -> str:
    if background.clutter is not None:
        return f"region {background.clutter} (Table 3.5)"
    if background.scr is not None:
        return f"SCR {background.scr:g}"
    if background.clutter_std is not None:
        return f"temperature spread {background.clutter_std:g} K → SCR per pair (Eq. (6.9))"
    if background.image is not None:
        return f"measured in {background.image} around each target (Eqs. (3.12)–(3.15))"
    if background.terrain is not None:
        return "terrain map (Eqs. (6.10)–(6.11)); not in the range curves, which need one SCR"
    return "none given: detection uses the transform"


def _atmosphere_text(atm: Any) -> str:
    if atm.extinction is not None:
        return f"extinction {atm.extinction * 1e3:g} Np/km"
    if atm.obscurant is not None:
        return f"Table 7.1 {atm.obscurant}, per sensor band"
    if atm.visibility is not None:
        return f"visibility {atm.visibility / 1e3:g} km ({atm.visibility_convention})"
    return "none"


def _report_sections(setup: RangeSetup) -> dict[str, dict[str, str]]:
    crit = setup.criterion
    sensor = {
        "IFOV": f"{setup.case.ifov * 1e3:.4g} mrad",
        "field of view": _field_of_view(setup),
        "resolvable cycle": f"{setup.cycle * 1e3:.4g} mrad "
        "(max of 2·IFOV and the optics, Eqs. (5.3), (5.2); Fig. 3.3)",
    }
    labels = {
        "pitch_m": ("pixel pitch", 1e6, "µm"),
        "focal_length_m": ("focal length", 1e3, "mm"),
        "hfov_rad": ("horizontal field of view", 180 / math.pi, "°"),
        "pixels": ("pixels across the field", 1, ""),
        "projection": ("field of view to IFOV", 1, "(targetacq.optics.FIELD_OF_VIEW_PROJECTIONS)"),
        "pixel_density": ("EN 62676-4 pixel density", 1, "definition"),
        "f_number": ("F-number", 1, ""),
    }
    for key, value in setup.sensor.items():
        name, scale, unit = labels[key]
        text = value if isinstance(value, str) else f"{value * scale:.4g}"
        sensor[name] = f"{text} {unit}".strip()
    optics_labels = {
        "aperture": ("aperture diameter", 1e3, "mm"),
        "wavelength": ("wavelength for diffraction", 1e6, "µm"),
        "blur_sigma": ("optics blur σ", 1e3, "mrad"),
    }
    for key, value in setup.optics.items():
        name, scale, unit = optics_labels[key]
        sensor[name] = f"{value * scale:.4g} {unit}"
    target = {
        "critical dimension": f"{setup.case.critical_dimension:.4g} m (smallest side seen, §3.2)"
    }
    scene_labels = {
        "target_temperature_k": ("target temperature", "K"),
        "background_temperature_k": ("background temperature", "K"),
        "contrast_w_per_m2": ("band exitance contrast", "W/m² (Eq. (6.12))"),
        "clutter_w_per_m2": ("clutter", "W/m² (background temperature spread × dM/dT)"),
        "scr": ("signal-to-clutter ratio", "(Eq. (6.9))"),
        "region": ("clutter region", "(Table 3.5)"),
    }
    for key, value in setup.scene.items():
        name, unit = scene_labels[key]
        text = f"{value:.4g}" if isinstance(value, float) else str(value)
        target[name] = f"{text} {unit}"
    path = (
        {
            "extinction": f"{setup.path['extinction_np_per_km']:.4g} Np/km "
            f"({setup.path['source']})",
            "description": setup.path["description"],
            "noise": "SNR = 20 log10(τ/(1−τ)) dB, Eqs. (7.5)–(7.7)",
            "noise model": f"{setup.case.noise_model}: "
            f"{NOISE_MODELS[setup.case.noise_model].source}",
        }
        if setup.path
        else {"atmosphere": "none (geometry, clutter and optics only)"}
    )
    n50s = ", ".join(f"{task} {crit.threshold(task):g}" for task in crit.tasks)
    model = {
        "criterion": f"{crit.name}: N50 {n50s} cycles ({crit.source})",
        "transform": f"{setup.case.transform}: {TRANSFORMS[setup.case.transform].source}"
        + "".join(f"; {k} = {v}" for k, v in setup.case.options.items()),
        "clutter": "detection from Table 3.5 (Schmieder–Weathersby) by SCR region; recognition "
        "and identification do not depend on clutter (§3.8)"
        if setup.case.in_clutter
        else "none given: detection uses the transform",
        "cycles on target": "N = (d / R) / cycle, small angle (Fig. 3.3)",
        "ordering": "P_id <= P_rec <= P_det: nothing is recognised that was not detected",
        "sources": _sources(),
    }
    return {
        "Sensor": sensor,
        "Target": target,
        "Path": path,
        "Model choices and sources": model,
    }
