"""The `clutter` command: clutter, SCR and features of targets in an image."""

from __future__ import annotations

import csv
import math
from typing import Annotated

import typer
import typer.main

from targetacq.acquisition.criteria import CRITERIA, get_criterion
from targetacq.acquisition.probabilities import Clutter
from targetacq.acquisition.probabilities import probability as probability_of
from targetacq.base.inputs import read_input_text
from targetacq.cli import (
    FORMATS,
    FormatOption,
    _render_rows,
    app,
)
from targetacq.io.images import read_image, save_clutter_overlay
from targetacq.physics.clutter import CHANNELS, as_boxes, gray, image_clutter
from targetacq.physics.features import target_features
from targetacq.run.range_options import option_choice, option_quantity

_BOX_COLUMNS = ("x", "y", "width", "height")


def _parse_box(text: str) -> list[float]:
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise ValueError(
            f"--box takes x,y,width,height in whole pixels, e.g. 40,60,12,8; got {text!r}"
        )
    return values


def _read_boxes(path: str) -> list[list[float]]:
    """The boxes of a CSV file with the columns x,y,width,height [pixels] (any order, other
    columns ignored); ``#`` lines are comments. Errors name the file, the line and the column."""
    try:
        text = read_input_text(path, "box file")
    except ValueError as error:
        raise ValueError(f"--boxes: {error}") from None
    header: list[str] | None = None
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = [cell.strip() for cell in next(csv.reader([line]))]
        if header is None:
            header = [cell.lower() for cell in cells]
            missing = [c for c in _BOX_COLUMNS if c not in header]
            if missing:
                raise ValueError(
                    f"--boxes {path}, line {number}: missing column {', '.join(missing)} "
                    f"(the header needs x,y,width,height; it names {', '.join(cells)})"
                )
            continue
        if len(cells) != len(header):
            raise ValueError(
                f"--boxes {path}, line {number}: {len(cells)} cells, but the header names "
                f"{len(header)} columns"
            )
        values = []
        for column in _BOX_COLUMNS:
            cell = cells[header.index(column)]
            try:
                value = float(cell)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise ValueError(
                    f"--boxes {path}, line {number}, column {column!r}: {cell!r} is not a "
                    "finite number of pixels"
                )
            values.append(value)
        rows.append(values)
    if not rows:
        raise ValueError(f"--boxes {path}: no box (a header x,y,width,height, then one per line)")
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
    image (Schmieder–Weathersby cells, Eqs. (3.12)–(3.15); features (2.6)–(2.12)).

    Example: targetacq clutter frame16.tif --boxes targets.csv (targetacq examples copy all .)
    """
    option_choice(output_format, FORMATS, "--format")
    all_boxes = [_parse_box(b) for b in box or []] + (_read_boxes(boxes) if boxes else [])
    if not all_boxes:
        raise ValueError("give at least one target: --box x,y,width,height or --boxes file.csv")
    if channel is not None:
        option_choice(channel, CHANNELS, "--channel")
    image = read_image(image_path)
    if channel is not None and image.ndim == 2:
        raise ValueError(f"--channel applies to a colour image; {image_path} is grayscale")
    pixels = gray(image, channel)
    if cycles is not None and (image_range or range_):
        raise ValueError("give --cycles, or --image-range with --range, not both")
    if (image_range is None) != (range_ is None):
        raise ValueError("--image-range and --range go together")
    scale = 1.0
    if image_range is not None and range_ is not None:
        # dri's reading of a length option: finite, > 0, within limits.MAX_LENGTH.
        r0 = option_quantity(image_range, "length", "--image-range")
        r1 = option_quantity(range_, "length", "--range")
        scale = r0 / r1
    if cycles is not None and not (math.isfinite(cycles) and cycles >= 0):
        raise ValueError(f"--cycles must be a finite number >= 0; got {cycles:g}")
    if not (math.isfinite(cell_factor) and cell_factor > 0):
        raise ValueError(f"--cell-factor must be a finite number > 0; got {cell_factor:g}")
    crit = get_criterion(option_choice(criterion, CRITERIA, "--criterion"))
    if not crit.gives_probabilities:
        raise ValueError(
            f"--criterion {criterion} gives pixel-density thresholds, not the P(detection) of "
            "this command; choose a criterion with cycles (e.g. johnson)"
        )
    result = image_clutter(pixels, all_boxes, cell_factor)
    b = as_boxes(all_boxes, pixels.shape)
    rows = []
    for k, (x, y, w, h) in enumerate(b):
        n = cycles if cycles is not None else min(w, h) / 2.0 * scale
        scr_value = float(result.scr[k])
        features = target_features(pixels, (x, y, w, h), cell_factor=cell_factor)
        p_det = (
            float(probability_of(n, "detection", crit, clutter=Clutter(scr=scr_value)))
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
