"""What a report says: the heading, sections, figures and captions of a report of a scenario, and
the range-performance curves of range cases with a caption that says where they stop.

Built here once for every front-end that writes reports (``targetacq report`` and the web
explorer's ``/report``); :mod:`targetacq.io.html_report` then renders the parts as HTML or PDF.
Nothing here is physics: the numbers come from :mod:`targetacq.core.ranges`, the core
(:mod:`targetacq.core.pair_ranges`) and :func:`targetacq.run.search.simulate`.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Mapping, Sequence
from typing import Any

from targetacq.acquisition.path_noise import NOISE_MODELS
from targetacq.acquisition.transforms import TRANSFORMS
from targetacq.core import ranges
from targetacq.core.cases import RangeCase
from targetacq.run.model_chain import ModelChain
from targetacq.run.range_options import RangeSetup, option_quantity
from targetacq.run.uncertainty import BAND, Uncertainty, uncertainty_curves, uncertainty_ranges
from targetacq.scenario.schema import load_scenario
from targetacq.sensors import get_sensor_type

# targetacq.reports.plots and targetacq.io.html_report (matplotlib, about 0.3 s) are imported by the
# functions that draw.

__all__ = [
    "FLOOR",
    "MAX_AUTO_RANGE",
    "REPORT_PROBABILITIES",
    "SIMULATION_RUNS",
    "SIMULATION_SEED",
    "SIMULATION_STEPS",
    "TERRAIN_NOT_TRACED",
    "atmosphere_figures",
    "case_title",
    "performance_and_note",
    "scenario_performance",
    "scenario_report",
    "sensor_text",
    "sources_line",
    "titled",
    "uncertainty_note",
    "uncertainty_section",
    "with_uncertainty",
]


REPORT_PROBABILITIES = "0.5,0.8,0.95"
"""The probabilities of a figure's or a report's DRI points unless --probability is given."""


def sources_line() -> str:
    """The model's source as a report prints it: the thesis, and where our errata and
    assumptions are written down (targetacq.io.html_report, with matplotlib, is imported on use)."""
    from targetacq.io.html_report import THESIS_CITATION

    return f"{THESIS_CITATION}; errata and assumptions: see the targetacq user guide"


FLOOR = 0.02
"""Automatic range axes extend until every task's probability is below this."""


MAX_AUTO_RANGE = 500e3
"""The longest automatic range axis [m]; the caption says where curves stop above the floor."""


SIMULATION_RUNS, SIMULATION_SEED, SIMULATION_STEPS = 500, 0, 240
"""Runs, seed and least number of time steps of a scenario report's simulated first times."""


def titled(heading: str, conditions: str) -> str:
    """A figure title: the heading, then the conditions wrapped to the figure's width.

    Examples
    --------
    >>> print(titled("Range performance", "weather none; no clutter; criterion johnson"))
    Range performance
    weather none; no clutter; criterion johnson
    """
    return "\n".join([heading, textwrap.fill(conditions, 100)])


def sensor_text(setup: RangeSetup) -> str:
    """A range case's sensor in words: its IFOV [mrad] and how it was given (pitch and focal
    length, field of view over pixels, or the IFOV itself)."""
    sensor = setup.sensor
    if "pitch_m" in sensor:
        pitch_um, focal_mm = sensor["pitch_m"] * 1e6, sensor["focal_length_m"] * 1e3
        optics_text = f"{pitch_um:.3g} µm pitch, {focal_mm:.4g} mm focal length"
    elif "hfov_rad" in sensor:
        optics_text = f"{math.degrees(sensor['hfov_rad']):.3g}° over {sensor['pixels']:.0f} pixels"
    else:
        optics_text = "IFOV given"
    return f"IFOV {setup.case.ifov * 1e3:.4g} mrad ({optics_text})"


def case_title(setup: RangeSetup) -> str:
    """A range case's title: its sensor (:func:`sensor_text`) and the target's critical
    dimension [m]."""
    return f"{sensor_text(setup)} — target critical dimension {setup.case.critical_dimension:.3g} m"


def performance_and_note(
    cases: Mapping[str, RangeCase],
    max_range: str | float | None,
    probabilities: Sequence[float],
    requirement: tuple[float, float | None] | None = None,
    reach: Sequence[float] = (),
) -> tuple[Any, str]:
    """Range performance of the cases on 600 ranges, and a caption saying where they stop.

    The range axis goes out to --max-range (text, or a number of metres); by default to a
    quarter beyond the farthest DRI range of the table (and the requirement's range, and the
    ranges of ``reach`` [m]: the 95 % points of uncertainty bands), so that every answer is on
    the chart and none is squeezed into its first few per cent; where no DRI range is finite,
    to where every task of every case is below :data:`FLOOR` (bounded by
    :data:`MAX_AUTO_RANGE` either way).
    """
    answers = [
        float(r)
        for case in cases.values()
        for p in probabilities
        for r in ranges.case_ranges(case, p).values()
    ] + [float(r) for r in reach]
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
        r_max = min(1.25 * max(answers), MAX_AUTO_RANGE)
        limit = "a quarter beyond the farthest DRI range of the table"
    else:
        reach = [
            float(r)
            for case in cases.values()
            for p in (FLOOR, min(probabilities))
            for r in ranges.case_ranges(case, p).values()
        ]
        finite = [r for r in reach if math.isfinite(r) and r > 0]
        r_max = min(1.05 * max(finite), MAX_AUTO_RANGE) if finite else 10e3
        limit = f"the automatic limit of {MAX_AUTO_RANGE / 1e3:g} km"
    grid = [r_max * (k + 1) / 600 for k in range(600)]
    performance = ranges.range_performance(grid, cases, probabilities)
    note = stop_note(performance, r_max, limit)
    if requirement is not None:
        p_text = "" if requirement[1] is None else f"P ≥ {requirement[1]:g} "
        note += f" Star and dashed line: the requirement, {p_text}at {requirement[0]:,.0f} m."
    return performance, note + " Dots: the DRI ranges of the table."


def with_uncertainty(performance: Any, uncertainty: Uncertainty) -> Any:
    """Range performance with the 5–95 % bands of its cases
    (:mod:`targetacq.run.uncertainty`).

    Adds ``<task>_p05`` and ``<task>_p95`` to the curves (dims ``case``, ``range``) and
    ``range_p05_m``, ``range_p50_m``, ``range_p95_m`` to the DRI table (NaN: never reached at
    that point). Each case's samples are one array pass of the core; the loop is over the
    cases. A spread applies to the cases that have its input
    (:meth:`targetacq.run.uncertainty.Uncertainty.applicable_to`).

    Parameters
    ----------
    performance : targetacq.core.cases.RangePerformance
        Of range cases (:func:`performance_and_note`), each with its :class:`RangeCase`.
    uncertainty : targetacq.run.uncertainty.Uncertainty

    Returns
    -------
    targetacq.core.cases.RangePerformance

    Examples
    --------
    >>> perf = ranges.range_performance([1e3, 6e3], {"clear": RangeCase(2.3, 2e-4)}, [0.5])
    >>> banded = with_uncertainty(perf, Uncertainty(100))
    >>> row = banded.dri.iloc[0]
    >>> bool(row["range_p05_m"] < row["range_m"] < row["range_p95_m"])
    True
    >>> sorted(v for v in banded.curves.data_vars if v.startswith("detection"))
    ['detection', 'detection_p05', 'detection_p95']
    """
    import dataclasses

    import numpy as np

    curves, dri = performance.curves.copy(), performance.dri.copy()
    grid = curves["range"].values
    labels = [str(c) for c in curves["case"].values]
    bands: dict[str, list[Any]] = {}
    for column in ("range_p05_m", "range_p50_m", "range_p95_m"):
        dri[column] = np.nan
    for label in labels:
        case = performance.cases[label]
        applied = uncertainty.applicable_to(case)
        for name, values in uncertainty_curves(case, grid, applied).items():
            if not name.endswith("_p50"):
                bands.setdefault(name, []).append(values)
        rows = dri["case"] == label
        probs = sorted(set(dri.loc[rows, "probability"]))
        found = uncertainty_ranges(case, probs, applied)
        for index in dri.index[rows]:
            task, p = dri.at[index, "task"], dri.at[index, "probability"]
            k = probs.index(p)
            for point in ("p05", "p50", "p95"):
                dri.at[index, f"range_{point}_m"] = float(found[task][point][k])
    for name, stacked in bands.items():
        curves[name] = (("case", "range"), np.stack(stacked))
    return dataclasses.replace(performance, curves=curves, dri=dri)


def uncertainty_note(uncertainty: Uncertainty) -> str:
    """A figure's caption for its band: the quantiles, samples, seed and spreads.

    Examples
    --------
    >>> print(uncertainty_note(Uncertainty(500, extinction_spread=0.2)))  # doctest: +ELLIPSIS
     Shaded: the 5–95 % band over 500 samples (seed 0) of lognormal inputs: N50 25 %, ...
    """
    spreads = _spread_text(uncertainty)
    return (
        f" Shaded: the {_band_text()} band over {uncertainty.samples} samples "
        f"(seed {uncertainty.seed}) of lognormal inputs: {spreads}; bars on the dots: the DRI "
        "ranges' bands."
    )


def _band_text() -> str:
    return f"{BAND[0] * 100:g}–{BAND[1] * 100:g} %"


def _spread_text(uncertainty: Uncertainty) -> str:
    names = {
        "n50_spread": "N50",
        "observer_spread": "observer",
        "netd_spread": "NETD",
        "extinction_spread": "extinction",
    }
    given = [
        f"{label} {getattr(uncertainty, name) * 100:.3g} %"
        for name, label in names.items()
        if getattr(uncertainty, name)
    ]
    return ", ".join(given) or "no spread"


def uncertainty_section(uncertainty: Uncertainty) -> dict[str, str]:
    """The report's section on its Monte Carlo: how many samples, the seed and each input's
    distribution, in words."""
    return {
        "samples": f"{uncertainty.samples} (seed {uncertainty.seed})",
        "band": f"{_band_text()} of the samples",
        "distributions": "lognormal, median at the nominal value, relative standard deviation "
        f"as stated: {_spread_text(uncertainty)}",
        "N50 spread": "Sonesson (2004) Table 3.2, ±25 % (default); one factor per sample for "
        "every task",
    }


def stop_note(performance: Any, r_max: float, limit: str) -> str:
    """Where the curves stop and why, naming the pairs still at or above :data:`FLOOR`."""
    last = performance.curves.isel(range=-1)
    above = [
        f"P({task}) {float(last[task].sel(case=case)):.2f} for {case}"
        for task in ("detection", "recognition", "identification")
        if task in last
        for case in [str(c) for c in last["case"].values]
        if float(last[task].sel(case=case)) >= FLOOR
    ]
    if above:
        return (
            f"The curves stop at {r_max / 1e3:.4g} km ({limit}), where "
            + ", ".join(above[:6])
            + (" and more" if len(above) > 6 else "")
            + f" (still at or above {FLOOR:.0%})."
        )
    return (
        f"The curves are drawn out to {r_max / 1e3:.4g} km, where every task's probability "
        f"is below {FLOOR:.0%}."
    )


def atmosphere_figures(
    bands: Sequence[tuple[float, float]], r_max: float, level: str, conditions: str
) -> dict[str, Any]:
    """One Table 7.1 figure per band in use, headed by the band."""
    from targetacq.physics.bands import band_name
    from targetacq.reports.plots import plot_atmosphere

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
            title=titled(
                f"Atmosphere, Table 7.1 {level} extinction, {name} band "
                f"({band[0] * 1e6:g}–{band[1] * 1e6:g} µm)",
                f"this report: {conditions}",
            ),
        )
    return figures


TERRAIN_NOT_TRACED = (
    " The ranges do not trace the scenario's [terrain] line of sight (a range line runs over "
    "open ground); evaluate and simulate trace it."
)
"""What a scenario's DRI ranges and range curves say of an elevation model they leave out."""


def scenario_performance(
    chain: Any, max_range: str | None, probabilities: list[float], axis: bool = True
) -> tuple[Any, str]:
    """Range performance of every sensor-target pair of a scenario, any sensor type, through
    the core (:func:`targetacq.core.pair_ranges.pair_performance`), and a caption saying where
    the curves stop.

    The range axis goes out to --max-range; by default (with ``axis``) to a quarter beyond the
    farthest DRI range, as the analyst's curves have it (a second pass of the core on that
    grid; the DRI ranges are searched once), else to where every task of every pair is below
    0.02 (1, 2, 4, … km).
    """
    from targetacq.core.pair_ranges import pair_performance

    rows = list(range(len(chain.compiled.scene.sensors.names)))
    how = (
        " Every pair through the core, each target moved away from the sensor along its start "
        "bearing. Dots: the DRI ranges of the table."
    ) + (TERRAIN_NOT_TRACED if chain.scenario.terrain is not None else "")
    if max_range is not None:
        r_max = option_quantity(max_range, "length", "--max-range")
        performance = pair_performance(
            chain, rows, probabilities, max_range=r_max, limit=MAX_AUTO_RANGE
        )
        return performance, stop_note(performance, r_max, f"--max-range {max_range}") + how
    performance = pair_performance(
        chain, rows, probabilities, limit=MAX_AUTO_RANGE, beyond_dri=1.25 if axis else None
    )
    found = [float(r) for r in performance.dri["range_m"] if math.isfinite(r) and r > 0]
    if axis and found:
        r_max = float(performance.curves["range"].values[-1])
        limit = "a quarter beyond the farthest DRI range of the table"
        return performance, stop_note(performance, r_max, limit) + how
    r_max = float(performance.curves["range"].values[-1])
    return performance, stop_note(performance, r_max, "the automatic limit") + how


def scenario_report(
    path: str, max_range: str | None, title: str | None, probabilities: list[float]
) -> tuple[Any, ...]:
    """Heading, range performance, sections, figures and captions of a scenario's report."""
    from targetacq.reports.plots import (
        plot_first_times,
        plot_range_performance,
        plot_timeline,
        plot_transforms,
    )
    from targetacq.run.search import simulate

    scenario = load_scenario(path)
    chain = ModelChain(scenario)
    performance, note = scenario_performance(chain, max_range, probabilities)
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
        + (f", {scenario.temperature(t):g} K" if t.temperature is not None else "")
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
            f"{model.noise_model or 'variance-sum'}: "
            f"{NOISE_MODELS[model.noise_model or 'variance-sum'].source}",
        },
        "Model choices and sources": {
            "transform": f"{model.transform}: {TRANSFORMS[model.transform].source}",
            "criteria": "; ".join(dict.fromkeys(f"{c.name} ({c.source})" for c in chain.criteria)),
            "fusion": "sensor level, P = 1 − Π(1 − P_s) over the sensors (Eq. (8.4))",
            "ordering": "P_id <= P_rec <= P_det: nothing is recognised that was not detected",
            "sources": sources_line(),
        },
    }
    figures = {
        "Range performance": plot_range_performance(
            performance,
            title=titled(f"{heading}: range performance per sensor–target pair", conditions),
        )
    }
    captions = {"Range performance": note}
    figures["Transforms"] = plot_transforms(
        scenario.model.criterion,
        title=titled(
            f"Resolution-to-probability transforms (criterion {scenario.model.criterion})",
            conditions,
        ),
    )
    if atm.obscurant is not None or atm.extinction is not None or atm.visibility is not None:
        _, _, level = (atm.obscurant or "").partition(":")
        r_max = float(performance.curves["range"].values[-1])
        figures.update(
            atmosphere_figures(
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
        title=titled(
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
        step = min(float(grid.step), duration / SIMULATION_STEPS)
        result = simulate(
            chain,
            duration=duration,
            step=step,
            runs=SIMULATION_RUNS,
            seed=SIMULATION_SEED,
        )
        figures["Simulated first times"] = plot_first_times(
            result,
            title=titled(
                f"{heading}: first times over {SIMULATION_RUNS} simulated runs "
                f"(seed {SIMULATION_SEED})" + (", fused over the sensors" if several else ""),
                conditions,
            ),
        )
        captions["Simulated first times"] = (
            f"Share of {SIMULATION_RUNS} runs (targetacq simulate, seed {SIMULATION_SEED}, "
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
        return (
            "terrain map (Eqs. (6.10)–(6.11)); in the range curves, the map around each target "
            "where it stands at the start"
        )
    return "none given: detection uses the transform"


def _atmosphere_text(atm: Any) -> str:
    if atm.extinction is not None:
        return f"extinction {atm.extinction * 1e3:g} Np/km"
    if atm.obscurant is not None:
        return f"Table 7.1 {atm.obscurant}, per sensor band"
    if atm.visibility is not None:
        return f"visibility {atm.visibility / 1e3:g} km ({atm.visibility_convention})"
    return "none"
