"""The `clutter` command: clutter, SCR and features of targets in an image."""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Annotated

import typer
import typer.main

from targetacq.acquisition import probability as probability_of
from targetacq.cli import (
    FORMATS,
    FormatOption,
    _choice,
    _render_rows,
    app,
)
from targetacq.clutter import CHANNELS, as_boxes, gray, image_clutter
from targetacq.criteria import CRITERIA, get_criterion
from targetacq.features import target_features
from targetacq.images import read_image, save_clutter_overlay
from targetacq.units import parse_quantity


def _parse_box(text: str) -> list[float]:
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 4:
        raise ValueError(f"--box takes x,y,width,height in pixels, e.g. 40,60,12,8; got {text!r}")
    return values


def _read_boxes(path: str) -> list[list[float]]:
    source = Path(path)
    if not source.is_file():
        raise ValueError(f"--boxes: no file {path!r}")
    with source.open(newline="") as handle:
        reader = csv.DictReader(row for row in handle if row.strip() and not row.startswith("#"))
        columns = [c.strip().lower() for c in reader.fieldnames or []]
        needed = ["x", "y", "width", "height"]
        if not all(c in columns for c in needed):
            raise ValueError(f"--boxes: {path!r} needs the columns x,y,width,height")
        rows = []
        for line, row in enumerate(reader, start=2):
            clean = {k.strip().lower(): v for k, v in row.items() if k}
            try:
                rows.append([float(clean[c]) for c in needed])
            except (TypeError, ValueError) as error:
                raise ValueError(f"--boxes: {path!r} line {line}: not four numbers") from error
    if not rows:
        raise ValueError(f"--boxes: {path!r} has no box")
    return rows


@app.command("clutter")
def clutter_command(
    image_path: Annotated[str, typer.Argument(metavar="IMAGE", help="PNG or TIFF (8/16-bit).")],
    box: Annotated[
        list[str] | None, typer.Option(help="Target box x,y,width,height [pixels]; repeatable.")
    ] = None,
    boxes: Annotated[
        str | None, typer.Option(help="CSV file with columns x,y,width,height [pixels].")
    ] = None,
    channel: Annotated[
        str | None, typer.Option(help=f"Channel of a colour image: {', '.join(CHANNELS)}.")
    ] = None,
    cell_factor: Annotated[
        float, typer.Option(help="Cell side over the box's minimum dimension.")
    ] = 2.0,
    cycles: Annotated[
        float | None, typer.Option(help="Cycles on target for P(detection) (default: box/2).")
    ] = None,
    image_range: Annotated[
        str | None, typer.Option(help="Range at which the image was taken, e.g. 1km.")
    ] = None,
    range_: Annotated[
        str | None, typer.Option("--range", help="Range to predict P(detection) at, e.g. 3km.")
    ] = None,
    criterion: Annotated[
        str, typer.Option(help="Criterion for the detection N50 (Johnson: 1 cycle).")
    ] = "johnson",
    overlay: Annotated[
        str | None, typer.Option(help="Write the image with cells and targets drawn (.png).")
    ] = None,
    output_format: FormatOption = "table",
) -> None:
    """Clutter, SCR (±), clutter region, signature features and P(detection) of targets in an
    image (Schmieder–Weathersby cells, Eqs. (3.12)–(3.15); features (2.6)–(2.12))."""
    _choice(output_format, FORMATS, "--format")
    all_boxes = [_parse_box(b) for b in box or []] + (_read_boxes(boxes) if boxes else [])
    if not all_boxes:
        raise ValueError("give at least one target: --box x,y,width,height or --boxes file.csv")
    pixels = gray(read_image(image_path), channel)
    if cycles is not None and (image_range or range_):
        raise ValueError("give --cycles, or --image-range with --range, not both")
    if (image_range is None) != (range_ is None):
        raise ValueError("--image-range and --range go together")
    scale = 1.0
    if image_range is not None and range_ is not None:
        r0 = parse_quantity(image_range, "length", "--image-range")
        r1 = parse_quantity(range_, "length", "--range")
        if not (r0 > 0 and r1 > 0):
            raise ValueError("--image-range and --range must be > 0")
        scale = r0 / r1
    if cycles is not None and not cycles >= 0:
        raise ValueError(f"--cycles must be >= 0; got {cycles}")
    crit = get_criterion(_choice(criterion, CRITERIA, "--criterion"))
    result = image_clutter(pixels, all_boxes, cell_factor)
    b = as_boxes(all_boxes, pixels.shape)
    rows = []
    for k, (x, y, w, h) in enumerate(b):
        n = cycles if cycles is not None else min(w, h) / 2.0 * scale
        scr_value = float(result.scr[k])
        features = target_features(pixels, (x, y, w, h), cell_factor=cell_factor)
        p_det = (
            float(probability_of(n, "detection", crit, scr=scr_value))
            if not math.isnan(scr_value)
            else math.nan
        )
        rows.append(
            {
                "target": k,
                "box": f"{x},{y},{w},{h}",
                "clutter": float(result.clutter[k]),
                "scr_positive": float(result.scr_positive[k]),
                "scr_negative": float(result.scr_negative[k]),
                "region": str(result.region[k]),
                "background_mean": float(result.background_mean[k]),
                "cycles": float(n),
                "p_detection": p_det,
                **{f: getattr(features, f) for f in _FEATURES},
            }
        )
    if overlay is not None:
        save_clutter_overlay(pixels, result, b, overlay)
    typer.echo(_render_rows(rows, output_format), nl=False)


_FEATURES = (
    "aspect",
    "std_over_mean",
    "compactness",
    "edge_strength",
    "form_factor",
    "mean_intensity",
    "contrast",
)
