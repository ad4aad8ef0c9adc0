"""The `plot` and `report` commands: figures and the HTML report."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Annotated, Any

import typer

from targetacq import __version__
from targetacq.acquisition.criteria import CRITERIA, get_criterion
from targetacq.acquisition.path_noise import NOISE_MODELS
from targetacq.acquisition.transforms import TRANSFORMS
from targetacq.cli import (
    app,
)
from targetacq.cli.options import range_case_options, uncertainty_options
from targetacq.io.files import output_path
from targetacq.physics.atmosphere import (
    EXTINCTION_LEVELS,
)
from targetacq.physics.bands import BANDS
from targetacq.reports.content import (
    REPORT_PROBABILITIES,
    atmosphere_figures,
    case_title,
    performance_and_note,
    scenario_report,
    sensor_text,
    sources_line,
    titled,
    uncertainty_note,
    uncertainty_section,
    with_uncertainty,
)
from targetacq.run.option_table import option_product, typed_options
from targetacq.run.range_options import (
    RangeSetup,
    option_band,
    option_choice,
    option_criterion,
    option_probabilities,
    option_quantity,
    range_setup,
)
from targetacq.run.uncertainty import Uncertainty, read_uncertainty, uncertainty_ranges

# targetacq.reports.plots and targetacq.io.html_report (matplotlib, about 0.3 s) are imported by the
# commands that draw, not when the CLI starts.

PLOT_KIND_NAMES = ("curves", "transforms", "atmosphere")
"""The names of :data:`targetacq.reports.plots.PLOT_KINDS`, known without importing matplotlib (for
the help text; a test keeps the two equal)."""


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
    if setup.path.get("model") == "named":
        weather = f"{setup.path['description']} (named atmosphere)"
    elif setup.path:
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
    from targetacq.reports.plots import (
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
        setup = range_setup(params, REPORT_PROBABILITIES)
        if not setup.criterion.gives_probabilities:
            raise ValueError(
                f"plot curves needs a criterion with probabilities (not {setup.criterion.name})"
            )
        performance, _ = performance_and_note(
            {"this sensor": setup.case}, max_range, setup.probabilities
        )
        conditions = _shared_conditions([_conditions(setup)])
        fig = plot_range_performance(
            performance, title=title or titled(case_title(setup), conditions)
        )
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
@uncertainty_options
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
    uncertainty_options: dict[str, Any],
) -> None:
    """Write a self-contained report (HTML, or PDF printed by headless Chromium): inputs, model
    choices with sources, the DRI table (at --probability, default 50 / 80 / 95 %) and the
    figures. Give a scenario file (every sensor-target pair becomes a case; takes
    --probability, --max-range and --title), or the sensor, target and path options of
    `targetacq dri`, where any option may take a list (`--critical-dimension 0.75m,2.3m
    --obscurant haze,fog:low`): one case per combination, all in one table and on shared
    figures.

    With --uncertainty N (range cases only), the DRI table and the range chart carry 5–95 %
    bands over N samples, as `targetacq dri --uncertainty` has them.

    Example: targetacq report --example --critical-dimension 0.75m,2.3m --out r.html
    """
    from targetacq.io.html_report import (
        REPORT_FORMATS,
        render_report,
        require_browser,
        write_report,
    )

    _, kind = output_path(out, REPORT_FORMATS, "the report file")  # before any work
    wanted = option_requirement(requirement)
    if kind == "pdf":
        require_browser()
    uncertainty = read_uncertainty(uncertainty_options)
    if scenario is not None:
        if uncertainty is not None:
            raise ValueError("--uncertainty takes range cases (the sensor options), not a scenario")
        _check_scenario_options(
            case_options, "a scenario report", "--probability, --max-range and --title"
        )
        probability = case_options.get("probability") or REPORT_PROBABILITIES
        parts = scenario_report(scenario, max_range, title, option_probabilities(probability))
    else:
        parts = _range_case_report(case_options, max_range, title, wanted, uncertainty)
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
    uncertainty: Uncertainty | None = None,
) -> tuple[Any, ...]:
    """Heading, range performance, sections, figures and captions of a report of range cases:
    one case per combination of the options given as lists; with ``uncertainty``, the bands of
    :func:`targetacq.reports.content.with_uncertainty` on the table and the range charts."""
    from targetacq.reports.plots import plot_range_performance, plot_transforms

    setups: dict[str, RangeSetup] = {}
    bands: list[tuple[float, float]] = []
    swept_names: list[str] = []
    for swept, options in option_product(case_options):
        setup = range_setup(options, REPORT_PROBABILITIES)
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
    reach = []
    if uncertainty is not None:  # the axis reaches the bands' 95 % points too
        uncertainty.check_cases(cases.values())
        for case in cases.values():
            found = uncertainty_ranges(case, probabilities, uncertainty.applicable_to(case))
            reach += [float(r) for task in found.values() for r in task["p95"]]
    performance, note = performance_and_note(
        cases, max_range, probabilities, requirement, reach=reach
    )
    if uncertainty is not None:
        performance = with_uncertainty(performance, uncertainty)
        note += uncertainty_note(uncertainty)
    conditions = _shared_conditions([_conditions(s) for s in setups.values()])
    if title:
        heading = title
    elif len(setups) == 1:
        heading = case_title(first)
    else:
        sensors = {sensor_text(s) for s in setups.values()}
        sensor = sensors.pop() if len(sensors) == 1 else "several sensors"
        heading = f"{sensor} — {len(setups)} cases over " + ", ".join(
            name.replace("_", " ") for name in swept_names
        )
    captions = {"Range performance": note}
    figures = {
        "Range performance": plot_range_performance(
            performance, title=titled(heading, conditions), requirement=requirement
        )
    }
    if requirement is not None:
        near, near_note = performance_and_note(
            cases, 2.0 * requirement[0], probabilities, requirement
        )
        if uncertainty is not None:
            near = with_uncertainty(near, uncertainty)
            near_note += uncertainty_note(uncertainty)
        figures["Range performance near the requirement"] = plot_range_performance(
            near, title=titled(heading, conditions), requirement=requirement
        )
        captions["Range performance near the requirement"] = near_note
    criteria = {s.criterion.name: s.criterion for s in setups.values()}
    for name, crit in criteria.items():
        key = "Transforms" if len(criteria) == 1 else f"Transforms, criterion {name}"
        figures[key] = plot_transforms(
            crit,
            title=titled(f"Resolution-to-probability transforms (criterion {name})", conditions),
        )
    r_max = float(performance.curves["range"].values[-1])
    levels = {
        s.path["source"].split(", ")[1]
        for s in setups.values()
        if s.path.get("source", "").startswith("Table 7.1")
    }
    level = levels.pop() if len(levels) == 1 else "nominal"
    figures.update(atmosphere_figures(bands, r_max, level, conditions))
    # What differs from case to case gets a column per case in each section (one table, no
    # cell that strings several cases' values together).
    sections = _merged_sections({label: _report_sections(s) for label, s in setups.items()})
    if uncertainty is not None:
        sections["Uncertainty (Monte Carlo)"] = uncertainty_section(uncertainty)
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
        "projection": (
            "field of view to IFOV",
            1,
            "(targetacq.physics.optics.FIELD_OF_VIEW_PROJECTIONS)",
        ),
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
            "extinction": f"{setup.path['extinction_np_per_km']:.4g} Np/km ({setup.path['source']})"
            if "extinction_np_per_km" in setup.path
            else f"named atmosphere, band {setup.path['band']} ({setup.path['source']})",
            "description": setup.path["description"],
            "noise": "SNR = 20 log10(τ/(1−τ)) dB, Eqs. (7.5)–(7.7)",
            "noise model": f"{setup.case.applied_noise_model}: "
            f"{NOISE_MODELS[setup.case.applied_noise_model].source}",
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
        "sources": sources_line(),
    }
    return {
        "Sensor": sensor,
        "Target": target,
        "Path": path,
        "Model choices and sources": model,
    }
