"""The `calibrate` command: a task's N50 (and exponent) fitted to a CSV file of trials."""

from __future__ import annotations

import csv
import math
from typing import Annotated, Any

import typer

from targetacq.acquisition.calibration import CriterionFit, fit_criterion
from targetacq.acquisition.criteria import CRITERIA, TASKS
from targetacq.acquisition.transforms import CLUTTER_REGIONS, TRANSFORMS
from targetacq.base.inputs import read_input_text
from targetacq.base.units import parse_quantity
from targetacq.cli import FORMATS, FormatOption, _complete, _csv, app
from targetacq.cli.params import Quantity
from targetacq.physics.optics import cycles_on_target, ifov
from targetacq.run.range_options import option_choice, option_quantity


def _quantity(kind: str, flag: str) -> dict[str, Any]:
    """A one-value quantity option's parser and metavar (``LENGTH``, ``ANGLE``)."""
    quantity = Quantity(kind, flag, lists=False)
    return {"parser": quantity, "metavar": quantity.metavar}


_OUTCOMES = {"1": 1.0, "0": 0.0, "true": 1.0, "false": 0.0, "yes": 1.0, "no": 0.0}


def read_trials(path: str) -> tuple[str, list[float], list[float]]:
    """The trials of a CSV file: ("cycles" or "range", the values [cycles or m], the outcomes).

    The header names ``outcome`` and one of ``cycles`` (cycles on target) or ``range`` (a
    length with its unit in each cell, e.g. ``1.2 km``); other columns are ignored, ``#`` lines
    are comments. An outcome is 1 / 0 (or true / false, yes / no). Errors name the file, the
    line and the column.
    """
    text = read_input_text(path, "trials file")
    header: list[str] | None = None
    kind = ""
    values: list[float] = []
    outcomes: list[float] = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = [cell.strip() for cell in next(csv.reader([line]))]
        where = f"{path}, line {number}"
        if header is None:
            header = [cell.lower() for cell in cells]
            kinds = [c for c in ("cycles", "range") if c in header]
            if "outcome" not in header or len(kinds) != 1:
                raise ValueError(
                    f"{where}: the header needs outcome and one of cycles or range (it names "
                    f"{', '.join(cells)})"
                )
            kind = kinds[0]
            continue
        if len(cells) != len(header):
            raise ValueError(
                f"{where}: {len(cells)} cells, but the header names {len(header)} columns"
            )
        cell = cells[header.index(kind)]
        if kind == "range":
            values.append(parse_quantity(cell, "length", f"{where}, column 'range'"))
        else:
            try:
                values.append(float(cell))
            except ValueError:
                raise ValueError(
                    f"{where}, column 'cycles': {cell!r} is not a number of cycles"
                ) from None
        outcome = cells[header.index("outcome")].lower()
        if outcome not in _OUTCOMES:
            raise ValueError(
                f"{where}, column 'outcome': {outcome!r} is not 1 or 0 (true/false, yes/no)"
            )
        outcomes.append(_OUTCOMES[outcome])
    if header is None or not values:
        raise ValueError(
            f"{path}: no trials (a header with outcome and cycles or range, then "
            "one line per trial)"
        )
    return kind, values, outcomes


def _cycles(
    kind: str,
    values: list[float],
    critical_dimension: str | None,
    ifov_text: str | None,
    pitch: str | None,
    focal_length: str | None,
) -> list[float]:
    """The trials' cycles: as given, or from ranges by the sensor's IFOV and the target's
    critical dimension, ``N = d / (2 IFOV R)``
    (:func:`targetacq.physics.optics.cycles_on_target`)."""
    sensor_given = any(v is not None for v in (critical_dimension, ifov_text, pitch, focal_length))
    if kind == "cycles":
        if sensor_given:
            raise ValueError(
                "--critical-dimension, --ifov, --pitch and --focal-length convert a range "
                "column to cycles; this file gives cycles"
            )
        return values
    if critical_dimension is None:
        raise ValueError("a range column needs --critical-dimension (of the target, e.g. 2.3m)")
    if (ifov_text is None) == (pitch is None or focal_length is None):
        raise ValueError("a range column needs the sensor: --ifov, or --pitch and --focal-length")
    if ifov_text is not None and (pitch is not None or focal_length is not None):
        raise ValueError("give either --ifov or --pitch and --focal-length, not both")
    if ifov_text is not None:
        angle = option_quantity(ifov_text, "angle", "--ifov")
    else:
        angle = float(
            ifov(
                option_quantity(pitch or "", "length", "--pitch"),
                option_quantity(focal_length or "", "length", "--focal-length"),
            )
        )
    size = option_quantity(critical_dimension, "length", "--critical-dimension")
    return [float(n) for n in cycles_on_target(size, values, angle)]


def _number(value: float) -> str:
    return "inf" if math.isinf(value) else f"{value:.4g}"


def _table(fit: CriterionFit, kind: str) -> str:
    percent = f"{100 * fit.confidence:g} %"
    cycles = "V50 [TTP cycles]" if fit.transform == "ttp" else "N50 [cycles]"
    lines = [
        f"task {fit.task}, transform {fit.transform}, {fit.trials} trials ({fit.successes} "
        f"successes){', cycles from ranges' if kind == 'range' else ''}",
        f"maximum likelihood; {percent} intervals by {fit.method}",
        "",
        f"{'parameter':<20}{'estimate':>10}{'low':>10}{'high':>10}",
        f"{cycles:<20}{_number(fit.n50):>10}{_number(fit.n50_interval[0]):>10}"
        f"{_number(fit.n50_interval[1]):>10}",
    ]
    if not math.isnan(fit.exponent):
        label = "E50 [1]" if fit.exponent_fitted else "E50 [1] (fixed)"
        low, high = fit.exponent_interval
        lines.append(
            f"{label:<20}{_number(fit.exponent):>10}"
            + (f"{_number(low):>10}{_number(high):>10}" if fit.exponent_fitted else "")
        )
    lines += [
        f"{'log-likelihood':<20}{fit.log_likelihood:>10.4f}",
        "",
        "criterion " + ", ".join(f"{t} {v:.4g}" for t, v in fit.criterion.thresholds.items()),
    ]
    reuse = _n50_option(fit)
    if reuse and fit.exponent_fitted:
        lines.append(
            "to use N50 in evaluations (they take the transform's own exponent), fit it with "
            "--fixed-exponent"
        )
    elif reuse:
        lines.append(f"use it: --n50 {reuse} (command line), n50 = [{reuse}] (scenario [model])")
    return "\n".join(lines) + "\n"


def _n50_option(fit: CriterionFit) -> str:
    thresholds = fit.criterion.thresholds
    wanted = ("detection", "recognition", "identification")
    if not all(t in thresholds for t in wanted):
        return ""
    return ",".join(f"{thresholds[t]:.4g}" for t in wanted)


def _row(fit: CriterionFit, kind: str) -> dict[str, Any]:
    row = fit.as_dict()
    row["input"] = kind
    row["n50_option"] = None if fit.exponent_fitted else (_n50_option(fit) or None)
    return row


@app.command("calibrate")
def calibrate_command(
    trials: Annotated[str, typer.Argument(help="CSV file: outcome and cycles (or range) columns.")],
    task: Annotated[
        str,
        typer.Option(
            help=f"The task the trials tested: {', '.join(TASKS)}.",
            autocompletion=_complete(TASKS, separator=None),
        ),
    ],
    transform: Annotated[
        str,
        typer.Option(
            help=f"Transform: {', '.join(TRANSFORMS)}.",
            autocompletion=_complete(tuple(TRANSFORMS), separator=None),
        ),
    ] = "ttpf",
    fixed_exponent: Annotated[
        bool,
        typer.Option(
            "--fixed-exponent",
            help="Fit N50 alone, with the transform's own exponent (the exponent is fitted "
            "too for ttpf and ttp otherwise).",
        ),
    ] = False,
    confidence: Annotated[
        float, typer.Option(help="Confidence of the intervals, in (0, 1).")
    ] = 0.9,
    base: Annotated[
        str,
        typer.Option(
            help="Criterion whose other tasks complete the fitted one, or none.",
            autocompletion=_complete(tuple(CRITERIA), separator=None),
        ),
    ] = "johnson",
    region: Annotated[
        str | None,
        typer.Option(
            help=f"Clutter region of schmieder-weathersby: {', '.join(CLUTTER_REGIONS)}.",
            autocompletion=_complete(CLUTTER_REGIONS, separator=None),
        ),
    ] = None,
    critical_dimension: Annotated[
        str | None,
        typer.Option(
            help="Critical dimension of the target, for a range column, e.g. 2.3m.",
            **_quantity("length", "--critical-dimension"),
        ),
    ] = None,
    ifov_text: Annotated[
        str | None,
        typer.Option(
            "--ifov",
            help="Pixel IFOV of the sensor, for a range column, e.g. 0.227mrad.",
            **_quantity("angle", "--ifov"),
        ),
    ] = None,
    pitch: Annotated[
        str | None,
        typer.Option(
            help="Pixel pitch, with --focal-length, for a range column, e.g. 17um.",
            **_quantity("length", "--pitch"),
        ),
    ] = None,
    focal_length: Annotated[
        str | None,
        typer.Option(
            help="Focal length, with --pitch, for a range column, e.g. 75mm.",
            **_quantity("length", "--focal-length"),
        ),
    ] = None,
    output_format: FormatOption = "table",
) -> None:
    """Fit a task's N50 (and, for ttpf and ttp, the exponent) to trials by maximum likelihood,
    with profile-likelihood intervals, and print the fit: N50, exponent at N50, their
    intervals, the log-likelihood and the number of trials.

    The CSV file has a header with outcome (1 success, 0 failure) and either cycles (cycles on
    target) or range (with its unit in each cell, e.g. 1.2 km; then --critical-dimension and the
    sensor, --ifov or --pitch and --focal-length, give the cycles).

    Example: targetacq calibrate trials.csv --task recognition --format json
    """
    option_choice(output_format, FORMATS, "--format")
    option_choice(transform, TRANSFORMS, "--transform")
    if base != "none":
        option_choice(base, CRITERIA, "--base")
    kind, values, outcomes = read_trials(trials)
    cycles = _cycles(kind, values, critical_dimension, ifov_text, pitch, focal_length)
    fit = fit_criterion(
        cycles,
        outcomes,
        task,
        transform=transform,
        fit_exponent=False if fixed_exponent else None,
        confidence=confidence,
        base=None if base == "none" else base,
        options=None if region is None else {"region": region},
    )
    if output_format == "json":
        from targetacq.io.files import json_text

        typer.echo(json_text(_row(fit, kind)))
    elif output_format == "csv":
        row = _row(fit, kind)
        flat = {
            **{k: v for k, v in row.items() if not isinstance(v, (list, dict))},
            "n50_low": fit.n50_interval[0],
            "n50_high": fit.n50_interval[1],
            "exponent_low": fit.exponent_interval[0],
            "exponent_high": fit.exponent_interval[1],
        }
        typer.echo(_csv([flat]), nl=False)
    else:
        typer.echo(_table(fit, kind), nl=False)
