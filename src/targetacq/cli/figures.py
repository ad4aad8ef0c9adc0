"""The `plot` and `report` commands: figures and the HTML report."""

from __future__ import annotations

import math
from collections.abc import Mapping
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
from targetacq.services.options import typed_options
from targetacq.services.range_case import (
    RangeSetup,
    option_band,
    option_choice,
    option_criterion,
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


def _title(setup: RangeSetup) -> str:
    sensor = setup.sensor
    if "pitch_m" in sensor:
        pitch_um, focal_mm = sensor["pitch_m"] * 1e6, sensor["focal_length_m"] * 1e3
        optics_text = f"{pitch_um:.3g} µm pitch, {focal_mm:.4g} mm focal length"
    elif "hfov_rad" in sensor:
        optics_text = f"{math.degrees(sensor['hfov_rad']):.3g}° over {sensor['pixels']:.0f} pixels"
    else:
        optics_text = "IFOV given"
    return (
        f"IFOV {setup.case.ifov * 1e3:.4g} mrad ({optics_text}) — target critical dimension "
        f"{setup.case.critical_dimension:.3g} m"
    )


def _performance(
    cases: Mapping[str, RangeCase], max_range: str | None, probabilities: list[float]
) -> Any:
    """Range performance of the cases on 400 ranges out to --max-range, or by default 1.3 times
    the longest range at which any case's task reaches the smallest probability."""
    if max_range is not None:
        r_max = option_quantity(max_range, "length", "--max-range")
    else:
        reach = [
            float(r)
            for case in cases.values()
            for r in ranges.case_ranges(case, min(probabilities)).values()
        ]
        finite = [r for r in reach if math.isfinite(r)]
        r_max = 1.3 * max(finite) if finite else 10e3
    grid = [r_max * (k + 1) / 400 for k in range(400)]
    return ranges.range_performance(grid, cases, probabilities)


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
    `atmosphere` takes --band."""
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
        performance = _performance({"this sensor": setup.case}, max_range, setup.probabilities)
        fig = plot_range_performance(performance, title=title or _title(setup))
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
    out: Annotated[str, typer.Option(help="Output file, .html.")],
    max_range: Annotated[
        str | None, typer.Option(help="Largest range of the curves, e.g. 8km (default: automatic).")
    ] = None,
    title: Annotated[str | None, typer.Option(help="Report title.")] = None,
    case_options: dict[str, Any],
) -> None:
    """Write a self-contained HTML report: inputs, model choices with sources, the DRI table at
    50 / 80 / 95 % and the figures. Give a scenario file (every sensor-target pair becomes a
    case), or every sensor, target and path option of `targetacq dri`."""
    from targetacq.plots import plot_atmosphere, plot_range_performance, plot_transforms
    from targetacq.report import render_report, write_report

    output_path(out, ("html", "htm"), "the report file")  # before any work
    given = _given(case_options)
    if scenario is not None:
        if given:
            unused = ", ".join("--" + name.replace("_", "-") for name in sorted(given))
            raise ValueError(f"a scenario report takes no sensor or target options; got {unused}")
        heading, performance, sections, figures = _scenario_report(scenario, max_range, title)
        page = render_report(performance, sections, figures, title=heading, version=__version__)
        typer.echo(f"wrote {write_report(out, page)}")
        return
    params = typed_options(case_options, "report")
    setup = range_setup(**params, default_probability=_REPORT_PROBABILITIES)
    if not setup.criterion.gives_probabilities:
        raise ValueError("the report needs a criterion with probabilities (not en62676-4)")
    performance = _performance({"this sensor": setup.case}, max_range, setup.probabilities)
    heading = title or _title(setup)
    figures = {"Range performance": plot_range_performance(performance, title=heading)}
    figures["Transforms"] = plot_transforms(setup.criterion)
    if setup.path and params["band"]:
        figures["Atmosphere"] = plot_atmosphere(option_band(params["band"]))
    page = render_report(
        performance, _report_sections(setup), figures, title=heading, version=__version__
    )
    written = write_report(out, page)
    typer.echo(f"wrote {written}")


def _scenario_report(path: str, max_range: str | None, title: str | None) -> tuple[Any, ...]:
    """Heading, range performance, sections and figures of a scenario's report."""
    from targetacq.plots import plot_atmosphere, plot_range_performance, plot_transforms

    scenario = load_scenario(path)
    chain = ModelChain(scenario)
    cases = chain.range_cases()
    performance = _performance(cases, max_range, [0.5, 0.8, 0.95])
    heading = title or (scenario.name or path)
    model = scenario.model
    sensors = {
        s.name: f"{s.type}, band {s.limits[0] * 1e6:g}–{s.limits[1] * 1e6:g} µm, IFOV "
        f"{s.pixel_ifov * 1e3:.4g} mrad"
        + (f", aperture {s.aperture * 1e3:g} mm" if s.aperture else "")
        for s in scenario.sensors
    }
    targets = {
        t.name: f"{' × '.join(f'{d:g}' for d in t.dimensions)} m, criterion "
        f"{chain.criteria[g].name}"
        + (f", {t.temperature:g} K" if t.temperature is not None else "")
        + (", moving" if t.moving else "")
        + (", hot spot" if t.hot_spot else "")
        for g, t in enumerate(scenario.targets)
    }
    atm = scenario.atmosphere
    sections = {
        "Scenario": {
            "file": path,
            "name": scenario.name or "(unnamed)",
            "cases": "every sensor–target pair, critical dimension as seen at the start",
        },
        "Sensors": sensors,
        "Targets": targets,
        "Background and path": {
            "clutter": _clutter_text(scenario.background),
            "atmosphere": _atmosphere_text(atm),
            "noise": "SNR = 20 log10(τ/(1−τ)) dB, Eqs. (7.5)–(7.7); noise model "
            f"{model.noise_model}: {NOISE_MODELS[model.noise_model].source}",
        },
        "Model choices and sources": {
            "transform": f"{model.transform}: {TRANSFORMS[model.transform].source}",
            "criteria": "; ".join(dict.fromkeys(f"{c.name} ({c.source})" for c in chain.criteria)),
            "ordering": "P_id <= P_rec <= P_det: nothing is recognised that was not detected",
            "sources": "Sonesson (2004), A Probabilistic Approach to Conceptual Sensor Modeling, "
            "LiTH-ISY-EX-3428; errata and open points as in targetacq's MODEL.md",
        },
    }
    figures = {"Range performance": plot_range_performance(performance, title=heading)}
    figures["Transforms"] = plot_transforms(scenario.model.criterion)
    if atm.obscurant is not None:
        figures["Atmosphere"] = plot_atmosphere(scenario.sensors[0].limits)
    return heading, performance, sections, figures


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
        "resolvable cycle": f"{setup.cycle * 1e3:.4g} mrad "
        "(max of 2·IFOV and the optics, Eqs. (5.3), (5.2); Fig. 3.3)",
    }
    labels = {
        "pitch_m": ("pixel pitch", 1e6, "µm"),
        "focal_length_m": ("focal length", 1e3, "mm"),
        "hfov_rad": ("horizontal field of view", 180 / math.pi, "°"),
        "pixels": ("pixels across the field", 1, ""),
    }
    for key, value in setup.sensor.items():
        name, scale, unit = labels[key]
        sensor[name] = f"{value * scale:.4g} {unit}".strip()
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
            "description": f"{setup.path['term']}, visual range {setup.path['visual_range']} "
            "(Table 7.2)",
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
        "sources": "Sonesson (2004), A Probabilistic Approach to Conceptual Sensor Modeling, "
        "LiTH-ISY-EX-3428; errata and open points as in targetacq's MODEL.md",
    }
    return {
        "Sensor": sensor,
        "Target": target,
        "Path": path,
        "Model choices and sources": model,
    }
