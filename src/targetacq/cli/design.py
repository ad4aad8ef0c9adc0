"""The `design` command: the focal length, pitch or IFOV at which a task reaches a probability.

The solver is :mod:`targetacq.run.design`; this module turns the range-case options into its
arguments (through :func:`targetacq.run.range_options.range_setup`, so every option is
checked as for ``dri``) and prints one line per task, probability, range and weather: without
the path's extinction, and with it where one is given.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Annotated, Any

import typer

from targetacq.base.limits import check_count
from targetacq.cli import FORMATS, FormatOption, _csv, _model_line, app
from targetacq.cli.options import range_case_options
from targetacq.io.files import json_text
from targetacq.run.option_table import typed_options
from targetacq.run.range_options import (
    example_camera,
    option_choice,
    option_quantity,
    range_setup,
)

# targetacq.run.design (NumPy, the model) is imported when the command runs.

_NOT_FOR_DESIGN = ("ifov", "hfov", "projection", "pixel_density", "mrtd")
"""Range-case options that give the resolution the design solves for."""

_NOT_MODEL = ("critical_dimension", "ifov", "cycle", "mrtd")


@app.command()
@range_case_options
def design(
    case_options: dict[str, Any],
    range_: Annotated[
        str,
        typer.Option(
            "--range",
            help="Range at which the task must reach the probability, or several separated by "
            "commas, e.g. 1km or 500m,1km.",
        ),
    ],
    task: Annotated[
        str | None,
        typer.Option(help="Task, e.g. recognition (default: every task of the criterion)."),
    ] = None,
    output_format: FormatOption = "table",
) -> None:
    """The focal length (with --pitch), the pitch (with --focal-length) or the IFOV (with
    neither) at which a task reaches a probability at a range, with and without the weather.

    It counts all that dri does: clutter, weather, sensor noise, diffraction and blur.

    Example: targetacq design --task recognition --range 1km --target person --pitch 12um
    """
    option_choice(output_format, FORMATS, "--format")
    report = design_report(typed_options(case_options, "design"), range_, task)
    typer.echo(_render(report, output_format), nl=False)


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def design_report(options: dict[str, Any], range_text: str, task: str | None) -> dict[str, Any]:
    """The design of the ``design`` command as a JSON-ready dict (rows: one per task,
    probability, range and weather)."""
    from targetacq.acquisition.transforms import get_transform
    from targetacq.run import design as solver

    options = dict(options)
    for name in _NOT_FOR_DESIGN:
        if options.get(name) is not None:
            what = (
                "an MRTD curve fixes the camera's resolution"
                if name == "mrtd"
                else f"{_flag(name)} gives the resolution the design solves for"
            )
            raise ValueError(
                f"{_flag(name)} does not apply to design ({what}); give --pitch (to find the "
                "focal length), --focal-length (to find the pitch) or neither (the IFOV)"
            )
    pitch, focal_length = options.pop("pitch"), options.pop("focal_length")
    # Pixels across the detector: each design's field of view, 2 atan(pixels · IFOV / 2)
    # (Eq. (5.1) with pitch / focal length = IFOV), as a datasheet would give it.
    pixels = options.pop("pixels", None)
    if pixels is not None:
        check_count("--pixels", pixels)
    if pitch is not None and focal_length is not None:
        raise ValueError(
            "give --pitch (design finds the focal length) or --focal-length (it finds the "
            "pitch), not both"
        )
    if options.get("example") and pitch is None and focal_length is None:
        pitch = example_camera()["pitch"]
    if options.get("f_number") is not None and pitch is None and focal_length is None:
        raise ValueError(
            "--f-number needs --pitch or --focal-length (aperture = focal length / F#)"
        )
    # A placeholder for the resolution solved for, so that range_setup checks every other option.
    if pitch is not None:
        p = option_quantity(pitch, "length", "--pitch")
        sensor = {"pitch": pitch, "focal_length": f"{p * 1e3!r}m", "ifov": None}
    elif focal_length is not None:
        f = option_quantity(focal_length, "length", "--focal-length")
        sensor = {"pitch": f"{f * 1e-3!r}m", "focal_length": focal_length, "ifov": None}
    else:
        sensor = {"pitch": None, "focal_length": None, "ifov": "1mrad"}
    setup = range_setup({**options, **sensor, "pixels": None}, "0.5")
    case, crit = setup.case, setup.criterion
    if crit.gives_probabilities:
        chosen = get_transform(case.transform)
        tasks = [t for t in crit.tasks if chosen.tasks is None or t in chosen.tasks]
    else:
        tasks = list(crit.tasks)
    wanted = tasks if task is None else [option_choice(task, tasks, "--task")]
    ranges = [option_quantity(part, "length", "--range") for part in range_text.split(",")]

    model = {
        field.name: getattr(case, field.name)
        for field in dataclasses.fields(case)
        if field.name not in _NOT_MODEL
    }
    lens: dict[str, Any] = {}
    if pitch is not None:
        lens["pitch"] = option_quantity(pitch, "length", "--pitch")
    if focal_length is not None:
        lens["focal_length"] = option_quantity(focal_length, "length", "--focal-length")
    if "f_number" in setup.sensor:
        lens["f_number"] = setup.sensor["f_number"]
        model["aperture"] = None
    solve_for = (
        "focal_length" if pitch is not None else "pitch" if focal_length is not None else "ifov"
    )
    weathers = [None, setup.path] if setup.path else [None]
    probabilities = setup.probabilities if crit.gives_probabilities else [math.nan]
    rows = []
    for weather in weathers:
        kw = dict(
            model,
            extinction=None if weather is None else case.extinction,
            path=None if weather is None else case.path,
        )
        for name in wanted:
            for p in probabilities:
                for r in ranges:
                    ifov = _solve(solver, solve_for, lens, case.critical_dimension, r, p, name, kw)
                    if math.isnan(ifov):
                        reason = solver.unreachable_reason(
                            case.critical_dimension,
                            r,
                            0.5 if math.isnan(p) else p,
                            name,
                            **lens,
                            **kw,
                        )
                        raise ValueError(
                            f"no {solve_for.replace('_', ' ')} reaches {name}"
                            + ("" if math.isnan(p) else f" with P = {p:g}")
                            + f" at {r:g} m: {reason}"
                        )
                    row: dict[str, Any] = {
                        "task": name,
                        "probability": None if math.isnan(p) else p,
                        "range_m": r,
                        "weather": None if weather is None else weather["source"],
                        "extinction_np_per_km": 0.0
                        if weather is None
                        else weather.get("extinction_np_per_km"),  # None: a named atmosphere
                        "ifov_rad": ifov,
                    }
                    if pixels is not None:
                        row["hfov_rad"] = 2.0 * math.atan(pixels * ifov / 2.0)
                    if solve_for == "focal_length":
                        row["focal_length_m"] = lens["pitch"] / ifov
                    elif solve_for == "pitch":
                        row["pitch_m"] = lens["focal_length"] * ifov
                    rows.append(row)
    return {
        "solve_for": solve_for,
        "sensor": {
            **{f"{k}_m": v for k, v in lens.items() if k != "f_number"},
            **({"f_number": lens["f_number"]} if "f_number" in lens else {}),
            **{f"{k}_{_SI[k]}": v for k, v in setup.optics.items() if "f_number" not in lens},
            **(
                {"wavelength_m": case.wavelength}
                if "f_number" in lens and case.wavelength is not None
                else {}
            ),
        },
        "target": {"critical_dimension_m": float(case.critical_dimension)},
        "path": setup.path,
        "criterion": crit.name,
        "transform": case.transform if crit.gives_probabilities else None,
        "options": case.options,
        "pixels": pixels,
        "rows": rows,
    }


_SI = {"aperture": "m", "wavelength": "m", "blur_sigma": "rad"}


def _solve(
    solver: Any,
    solve_for: str,
    lens: dict[str, Any],
    critical_dimension: float,
    r: float,
    p: float,
    task: str,
    model: dict[str, Any],
) -> float:
    """The IFOV [rad] of one design, from the solver for ``solve_for`` (NaN: none reaches it)."""
    p = 0.5 if math.isnan(p) else p  # a pixel-density criterion: no probability
    f_number = lens.get("f_number")
    if solve_for == "focal_length":
        f = solver.required_focal_length(
            lens["pitch"], critical_dimension, r, p, task, f_number=f_number, **model
        )
        return float(lens["pitch"] / f)
    if solve_for == "pitch":
        pitch = solver.required_pitch(
            lens["focal_length"], critical_dimension, r, p, task, f_number=f_number, **model
        )
        return float(pitch / lens["focal_length"])
    return float(solver.required_ifov(critical_dimension, r, p, task, **model))


def _render(report: dict[str, Any], output_format: str) -> str:
    rows = report["rows"]
    if output_format == "json":
        return json_text(report) + "\n"
    if output_format == "csv":
        return _csv(rows)
    solve_for = report["solve_for"]
    sensor = report["sensor"]
    given = {
        "focal_length": f"pitch {sensor.get('pitch_m', math.nan) * 1e6:.4g} µm",
        "pitch": f"focal length {sensor.get('focal_length_m', math.nan) * 1e3:.4g} mm",
        "ifov": "",
    }[solve_for]
    lines = [
        _model_line(report),
        f"target: critical dimension {report['target']['critical_dimension_m']:.4g} m"
        + (f"; {given}" if given else ""),
    ]
    if report["path"] and report["path"].get("model") == "named":
        path = report["path"]
        lines.append(
            f"weather: {path['description']}, band {path['band']} (named atmosphere, LOWTRAN7 "
            "table); each design without it and with it"
        )
    elif report["path"]:
        path = report["path"]
        lines.append(
            f"weather: extinction {path['extinction_np_per_km']:.4g} Np/km ({path['term']}; "
            f"{path['source']}); each design without it and with it"
        )
    lines.append("")
    wanted = {
        "focal_length": ("focal length [mm]", "focal_length_m", 1e3),
        "pitch": ("pitch [µm]", "pitch_m", 1e6),
        "ifov": ("IFOV [mrad]", "ifov_rad", 1e3),
    }[solve_for]
    header = f"{'task':<16}{'P':>6}  {'range [m]':>10}  {'weather':>14}  {wanted[0]:>18}"
    if solve_for != "ifov":
        header += f"  {'IFOV [mrad]':>12}"
    if report["pixels"] is not None:
        header += f"  {'FOV [deg]':>10}"
    lines += [header, "-" * len(header)]
    for row in rows:
        p = "-" if row["probability"] is None else f"{row['probability']:.2f}"
        weather = (
            "none"
            if row["weather"] is None
            else "named"
            if row["extinction_np_per_km"] is None
            else f"{row['extinction_np_per_km']:.4g} Np/km"
        )
        line = (
            f"{row['task']:<16}{p:>6}  {row['range_m']:>10,.0f}  {weather:>14}  "
            f"{row[wanted[1]] * wanted[2]:>18.4g}"
        )
        if solve_for != "ifov":
            line += f"  {row['ifov_rad'] * 1e3:>12.4g}"
        if report["pixels"] is not None:
            line += f"  {math.degrees(row['hfov_rad']):>10.4g}"
        lines.append(line)
    return "\n".join(lines) + "\n"
