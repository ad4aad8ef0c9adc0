"""The ``targetacq`` command.

Every quantity takes a unit (``--pitch 17um``); choices come from the registries. Bad input
prints one line on stderr and exits with status 2, never a traceback.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import sys
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
import typer.main

from targetacq import __version__, atmosphere, optics, radiometry, ranges
from targetacq import clutter as clutter_module
from targetacq.acquisition import probability as probability_of
from targetacq.atmosphere import (
    EXTINCTION_LEVELS,
    OBSCURANTS,
    VISIBILITY_CONVENTIONS,
    np_per_km_to_db_per_km,
)
from targetacq.bands import BANDS, band_limits, band_name
from targetacq.clutter import CHANNELS, as_boxes, gray, image_clutter
from targetacq.criteria import CRITERIA, Criterion, get_criterion
from targetacq.features import target_features
from targetacq.images import read_image, save_clutter_overlay
from targetacq.model import ModelChain
from targetacq.noise import NOISE_MODELS
from targetacq.plots import (
    PLOT_KINDS,
    plot_atmosphere,
    plot_range_performance,
    plot_transforms,
    save_figure,
)
from targetacq.report import render_report, write_report
from targetacq.scenario import load_scenario
from targetacq.search import simulate as simulate_runs
from targetacq.tables import load_table
from targetacq.transforms import C2NVEO_BOUNDS, CLUTTER_REGIONS, TRANSFORMS
from targetacq.units import parse_quantity

__all__ = ["app", "main"]

FORMATS = ("table", "json", "csv")
DEFAULT_EXAMPLE = "uav_haze.toml"
_SI_SUFFIX = {"aperture": "m", "wavelength": "m", "blur_sigma": "rad"}

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Probabilities and ranges of detection, recognition and identification for imaging "
    "sensors (Sonesson 2004 conceptual sensor model).",
)


# Options shared by several commands, defined once.
BandOption = Annotated[
    str | None, typer.Option(help=f"Sensor band: {', '.join(BANDS)} or e.g. 8-12um.")
]
ExtinctionOption = Annotated[
    str | None, typer.Option(help="Path extinction, e.g. 0.4/km (Np/km) or 1.7dB/km.")
]
ObscurantOption = Annotated[
    str | None,
    typer.Option(help=f"Table 7.1 obscurant[:low|nominal|high]: {', '.join(OBSCURANTS)}."),
]
VisibilityOption = Annotated[
    str | None, typer.Option(help="Visibility (visible band), e.g. 7.5km.")
]
ConventionOption = Annotated[
    str | None,
    typer.Option(help=f"Visibility convention: {', '.join(VISIBILITY_CONVENTIONS)}."),
]
FormatOption = Annotated[str, typer.Option("--format", help=f"Output: {', '.join(FORMATS)}.")]


@app.callback()
def _root() -> None:
    """Probabilities and ranges of detection, recognition and identification."""


def _example_camera() -> dict[str, str]:
    table = load_table("example_camera")
    return {
        quantity: f"{value} {unit}".strip()
        for quantity, value, unit in zip(
            table.column("quantity"), table.column("value"), table.column("unit"), strict=True
        )
    }


def _choice(value: str, choices: Any, name: str) -> str:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(choices)}; got {value!r}")
    return value


def _probabilities(text: str) -> list[float]:
    values = []
    for part in text.split(","):
        try:
            p = float(part)
        except ValueError as error:
            raise ValueError(f"--probability: {part!r} is not a number in (0, 1)") from error
        if not 0 < p < 1:
            raise ValueError(f"--probability must be in the open interval (0, 1); got {part}")
        values.append(p)
    return values


def _user_criterion(text: str) -> Criterion:
    parts = text.split(",")
    if len(parts) != 3:
        raise ValueError(f"--n50 takes three numbers D,R,I (cycles), e.g. 1,4,6.4; got {text!r}")
    try:
        values = [float(p) for p in parts]
    except ValueError as error:
        raise ValueError(f"--n50 takes three numbers D,R,I (cycles); got {text!r}") from error
    if not all(math.isfinite(v) and v > 0 for v in values):
        raise ValueError(f"--n50 values must be finite and > 0 cycles; got {text!r}")
    return get_criterion(
        dict(zip(("detection", "recognition", "identification"), values, strict=True))
    )


def _sensor_ifov(
    pitch: str | None,
    focal_length: str | None,
    ifov: str | None,
    hfov: str | None,
    pixels: int | None,
) -> tuple[float, dict[str, float]]:
    ways = [
        pitch is not None or focal_length is not None,
        ifov is not None,
        hfov is not None or pixels is not None,
    ]
    if sum(ways) != 1:
        raise ValueError(
            "give the sensor's resolution one way: --pitch and --focal-length, or --ifov, or "
            "--hfov and --pixels (or --example)"
        )
    if ways[0]:
        if pitch is None or focal_length is None:
            raise ValueError("--pitch and --focal-length go together")
        p = parse_quantity(pitch, "length", "--pitch")
        f = parse_quantity(focal_length, "length", "--focal-length")
        return float(optics.ifov(p, f)), {"pitch_m": p, "focal_length_m": f}
    if ways[1]:
        assert ifov is not None
        value = parse_quantity(ifov, "angle", "--ifov")
        if not value > 0:
            raise ValueError(f"--ifov must be > 0; got {ifov!r}")
        return value, {}
    if hfov is None or pixels is None:
        raise ValueError("--hfov and --pixels go together")
    fov = parse_quantity(hfov, "angle", "--hfov")
    value = float(optics.ifov_from_field_of_view(fov, pixels))
    return value, {"hfov_rad": fov, "pixels": float(pixels)}


def _band(text: str) -> tuple[float, float]:
    """A named band, or "8-12um"-style limits, as (λ1, λ2) [m]."""
    if text in BANDS:
        return BANDS[text]
    match = re.fullmatch(r"\s*([\d.]+)\s*-\s*([\d.]+)\s*([A-Za-zµ]+)\s*", text)
    if match is None:
        raise ValueError(f"--band must be one of {', '.join(BANDS)} or like 8-12um; got {text!r}")
    low, high, unit = match.groups()
    limits = (
        parse_quantity(f"{low} {unit}", "length", "--band"),
        parse_quantity(f"{high} {unit}", "length", "--band"),
    )
    return band_limits(limits)


def _path(
    extinction: str | None,
    obscurant: str | None,
    visibility: str | None,
    convention: str | None,
    band: tuple[float, float] | None,
) -> dict[str, Any]:
    """The path's extinction from one of --extinction, --obscurant, --visibility ({} if none)."""
    given = [v is not None for v in (extinction, obscurant, visibility)]
    if sum(given) > 1:
        raise ValueError("give one of --extinction, --obscurant and --visibility")
    if convention is not None and visibility is None:
        raise ValueError("--visibility-convention goes with --visibility")
    if extinction is not None:
        gamma = parse_quantity(extinction, "extinction", "--extinction")
        if not gamma >= 0:
            raise ValueError(f"--extinction must be >= 0; got {extinction!r}")
        info: dict[str, Any] = {"source": f"--extinction {extinction}"}
    elif obscurant is not None:
        if band is None:
            raise ValueError("--obscurant needs --band (Table 7.1 depends on the band)")
        name, _, level = obscurant.partition(":")
        _choice(name, OBSCURANTS, "--obscurant")
        level = level or "nominal"
        _choice(level, EXTINCTION_LEVELS, "--obscurant level")
        gamma = atmosphere.obscurant_extinction(name, band, level)
        info = {"source": f"Table 7.1: {name}, {level}, {band_name(band)}"}
    elif visibility is not None:
        if band is not None and band_name_or_none(band) != "visible":
            raise ValueError(
                "--visibility gives the visible-band extinction; for an infrared --band give "
                "--extinction or --obscurant"
            )
        if convention is None:
            raise ValueError(
                "--visibility needs --visibility-convention koschmieder (2 % contrast, 3.912/V) "
                "or mor (5 %, 2.996/V)"
            )
        _choice(convention, VISIBILITY_CONVENTIONS, "--visibility-convention")
        v = parse_quantity(visibility, "length", "--visibility")
        gamma = float(atmosphere.extinction_from_visibility(v, convention))
        info = {"source": f"visibility {visibility} ({convention})"}
    else:
        return {}
    term, visual_range = atmosphere.extinction_term(gamma)
    return {
        "extinction_np_per_m": gamma,
        "extinction_np_per_km": gamma * 1e3,
        "term": term,
        "visual_range": visual_range,
        **info,
    }


def band_name_or_none(band: tuple[float, float]) -> str | None:
    try:
        return band_name(band)
    except ValueError:
        return None


def _clutter(
    scr: float | None,
    region: str | None,
    clutter_std: str | None,
    target_temperature: str | None,
    background_temperature: str | None,
    emissivity: float,
    background_emissivity: float,
    band: tuple[float, float] | None,
) -> dict[str, Any]:
    """SCR or clutter region from --scr, --clutter, or temperatures with --clutter-std."""
    if sum(v is not None for v in (scr, region, clutter_std)) > 1:
        raise ValueError("give one of --scr, --clutter and --clutter-std")
    temperatures = (target_temperature, background_temperature)
    if any(t is not None for t in temperatures) and None in temperatures:
        raise ValueError("--target-temperature and --background-temperature go together")
    if scr is not None:
        if not scr >= 0:
            raise ValueError(f"--scr must be >= 0; got {scr}")
        return {"scr": scr}
    if region is not None:
        return {"region": _choice(region, CLUTTER_REGIONS, "--clutter")}
    info: dict[str, Any] = {}
    if target_temperature is not None and background_temperature is not None:
        if band is None:
            raise ValueError("temperatures need --band to compute the band exitance")
        t_t = parse_quantity(target_temperature, "temperature", "--target-temperature")
        t_b = parse_quantity(background_temperature, "temperature", "--background-temperature")
        for name, eps in (
            ("--emissivity", emissivity),
            ("--background-emissivity", background_emissivity),
        ):
            if not 0 <= eps <= 1:
                raise ValueError(f"{name} must be in [0, 1]; got {eps}")
        m_t = emissivity * float(radiometry.band_exitance(t_t, band))
        m_b = background_emissivity * float(radiometry.band_exitance(t_b, band))
        info = {
            "target_temperature_k": t_t,
            "background_temperature_k": t_b,
            "contrast_w_per_m2": abs(m_t - m_b),
        }
        if clutter_std is not None:
            sigma_t = parse_quantity(clutter_std, "temperature difference", "--clutter-std")
            if not sigma_t >= 0:
                raise ValueError(f"--clutter-std must be >= 0; got {clutter_std!r}")
            sigma_m = (
                background_emissivity
                * float(radiometry.band_exitance_derivative(t_b, band))
                * sigma_t
            )
            info["clutter_w_per_m2"] = sigma_m
            info["scr"] = float(clutter_module.signal_to_clutter_ratio(m_t, m_b, sigma_m))
    elif clutter_std is not None:
        raise ValueError("--clutter-std needs --target-temperature and --background-temperature")
    return info


@app.command()
def dri(
    pitch: Annotated[str | None, typer.Option(help="Pixel pitch, e.g. 17um.")] = None,
    focal_length: Annotated[str | None, typer.Option(help="Focal length, e.g. 75mm.")] = None,
    ifov: Annotated[str | None, typer.Option(help="Pixel IFOV, e.g. 0.227mrad.")] = None,
    hfov: Annotated[str | None, typer.Option(help="Horizontal field of view, e.g. 12deg.")] = None,
    pixels: Annotated[int | None, typer.Option(help="Pixels across --hfov, e.g. 640.")] = None,
    aperture: Annotated[
        str | None, typer.Option(help="Lens aperture diameter for diffraction, e.g. 75mm.")
    ] = None,
    wavelength: Annotated[
        str | None, typer.Option(help="Wavelength for diffraction, e.g. 10um.")
    ] = None,
    blur: Annotated[
        str | None, typer.Option(help="Angular std. dev. of a Gaussian optics blur, e.g. 0.05mrad.")
    ] = None,
    critical_dimension: Annotated[
        str | None, typer.Option(help="Target critical dimension, e.g. 2.3m.")
    ] = None,
    criterion: Annotated[
        str, typer.Option(help=f"Criteria set: {', '.join(CRITERIA)}.")
    ] = "johnson",
    n50: Annotated[
        str | None,
        typer.Option(help="User-defined N50 cycles for detection,recognition,identification."),
    ] = None,
    transform: Annotated[str, typer.Option(help=f"Transform: {', '.join(TRANSFORMS)}.")] = "ttpf",
    bound: Annotated[
        str | None, typer.Option(help=f"c2nveo bound: {', '.join(C2NVEO_BOUNDS)}.")
    ] = None,
    scr: Annotated[
        float | None, typer.Option(help="Signal-to-clutter ratio (schmieder-weathersby).")
    ] = None,
    clutter: Annotated[
        str | None,
        typer.Option(help=f"Clutter region (schmieder-weathersby): {', '.join(CLUTTER_REGIONS)}."),
    ] = None,
    band: BandOption = None,
    target_temperature: Annotated[
        str | None, typer.Option(help="Target temperature, e.g. 305K or 32degC.")
    ] = None,
    background_temperature: Annotated[
        str | None, typer.Option(help="Background temperature, e.g. 295K.")
    ] = None,
    emissivity: Annotated[float, typer.Option(help="Target emissivity in [0, 1].")] = 1.0,
    background_emissivity: Annotated[
        float, typer.Option(help="Background emissivity in [0, 1].")
    ] = 1.0,
    clutter_std: Annotated[
        str | None,
        typer.Option(help="Background temperature spread (clutter), e.g. 2K; gives the SCR."),
    ] = None,
    extinction: ExtinctionOption = None,
    obscurant: ObscurantOption = None,
    visibility: VisibilityOption = None,
    visibility_convention: ConventionOption = None,
    noise_model: Annotated[
        str, typer.Option(help=f"Noise model: {', '.join(NOISE_MODELS)}.")
    ] = "variance-sum",
    probability: Annotated[
        str, typer.Option(help="Probability, or several separated by commas, e.g. 0.5,0.8.")
    ] = "0.5",
    output_format: FormatOption = "table",
    example: Annotated[
        bool, typer.Option("--example", help="Use the bundled example camera and target.")
    ] = False,
) -> None:
    """Ranges at which each task (detection, recognition, identification) reaches a probability."""
    _choice(output_format, FORMATS, "--format")
    params = dict(locals())
    params.pop("output_format")
    setup = _setup(**params)
    typer.echo(_render(_dri_report(setup), output_format), nl=False)


@dataclass(frozen=True)
class _Setup:
    """Everything the dri, plot and report commands read from the sensor/target/path options."""

    critical_dimension: float
    ifov: float
    sensor: dict[str, float]
    optics: dict[str, Any]
    criterion: Criterion
    transform: str
    options: dict[str, Any]
    path: dict[str, Any]
    scene: dict[str, Any]
    noise_model: str
    probabilities: list[float]

    @property
    def clutter(self) -> dict[str, Any]:
        return {k: self.scene[k] for k in ("scr", "region") if self.scene.get(k) is not None}

    @property
    def cycle(self) -> float:
        return float(optics.resolvable_cycle_angle(self.ifov, **self.optics))

    def case(self) -> dict[str, Any]:
        """The setup as a case of :func:`targetacq.ranges.range_performance`."""
        return {
            "critical_dimension": self.critical_dimension,
            "ifov": self.ifov,
            "criterion": self.criterion,
            "transform": self.transform,
            "extinction": self.path.get("extinction_np_per_m"),
            "noise_model": self.noise_model,
            "options": self.options,
            **self.optics,
            **self.clutter,
        }


def _setup(
    pitch: str | None,
    focal_length: str | None,
    ifov: str | None,
    hfov: str | None,
    pixels: int | None,
    aperture: str | None,
    wavelength: str | None,
    blur: str | None,
    critical_dimension: str | None,
    criterion: str,
    n50: str | None,
    transform: str,
    bound: str | None,
    scr: float | None,
    clutter: str | None,
    band: str | None,
    target_temperature: str | None,
    background_temperature: str | None,
    emissivity: float,
    background_emissivity: float,
    clutter_std: str | None,
    extinction: str | None,
    obscurant: str | None,
    visibility: str | None,
    visibility_convention: str | None,
    noise_model: str,
    probability: str,
    example: bool,
) -> _Setup:
    _choice(transform, TRANSFORMS, "--transform")
    if example:
        camera = _example_camera()
        if ifov is None and hfov is None and pixels is None:
            pitch = pitch or camera["pitch"]
            focal_length = focal_length or camera["focal_length"]
        if blur is None:
            aperture = aperture or camera["aperture"]
            wavelength = wavelength or camera["wavelength"]
        critical_dimension = critical_dimension or camera["critical_dimension"]
    if critical_dimension is None:
        raise ValueError("--critical-dimension is required (e.g. 2.3m), or use --example")
    d = parse_quantity(critical_dimension, "length", "--critical-dimension")
    if not d > 0:
        raise ValueError(f"--critical-dimension must be > 0; got {critical_dimension!r}")
    ifov_rad, sensor = _sensor_ifov(pitch, focal_length, ifov, hfov, pixels)
    optics_kw: dict[str, Any] = {}
    if (aperture is None) != (wavelength is None):
        raise ValueError("--aperture and --wavelength go together (diffraction limit)")
    if aperture is not None and wavelength is not None:
        optics_kw["aperture"] = parse_quantity(aperture, "length", "--aperture")
        optics_kw["wavelength"] = parse_quantity(wavelength, "length", "--wavelength")
    if blur is not None:
        optics_kw["blur_sigma"] = parse_quantity(blur, "angle", "--blur")
    if n50 is not None and criterion != "johnson":
        raise ValueError("give either --criterion or --n50, not both")
    crit = (
        _user_criterion(n50)
        if n50 is not None
        else get_criterion(_choice(criterion, CRITERIA, "--criterion"))
    )
    options: dict[str, Any] = {}
    if bound is not None:
        options["bound"] = _choice(bound, C2NVEO_BOUNDS, "--bound")
    band_limits_m = _band(band) if band is not None else None
    path = _path(extinction, obscurant, visibility, visibility_convention, band_limits_m)
    scene = _clutter(
        scr,
        clutter,
        clutter_std,
        target_temperature,
        background_temperature,
        emissivity,
        background_emissivity,
        band_limits_m,
    )
    _choice(noise_model, NOISE_MODELS, "--noise-model")
    return _Setup(
        critical_dimension=d,
        ifov=ifov_rad,
        sensor=sensor,
        optics=optics_kw,
        criterion=crit,
        transform=transform,
        options=options,
        path=path,
        scene=scene,
        noise_model=noise_model,
        probabilities=_probabilities(probability),
    )


def _dri_report(setup: _Setup) -> dict[str, Any]:
    crit = setup.criterion

    rows = []
    for p in setup.probabilities:
        found = ranges.dri_ranges(
            setup.critical_dimension,
            setup.ifov,
            crit,
            probability=p,
            transform=setup.transform,
            extinction=setup.path.get("extinction_np_per_m"),
            noise_model=setup.noise_model,
            **setup.optics,
            **setup.clutter,
            **setup.options,
        )
        for task, r in found.items():
            value = float(r)
            rows.append(
                {
                    "task": task,
                    "probability": p if crit.gives_probabilities else None,
                    "threshold": crit.threshold(task),
                    "threshold_unit": "cycles" if crit.gives_probabilities else "pixels/m",
                    "range_m": value if math.isfinite(value) else None,
                    "reached": not math.isnan(value),
                }
            )
        if not crit.gives_probabilities:
            break
    return {
        "sensor": {
            "ifov_rad": setup.ifov,
            "cycle_rad": setup.cycle,
            **setup.sensor,
            **{f"{k}_{_SI_SUFFIX[k]}": v for k, v in setup.optics.items()},
        },
        "target": {"critical_dimension_m": setup.critical_dimension, **setup.scene},
        "path": setup.path,
        "criterion": crit.name,
        "criterion_kind": crit.kind,
        "transform": setup.transform if crit.gives_probabilities else None,
        "options": setup.options,
        "noise_model": setup.noise_model if setup.path else None,
        "ranges": rows,
    }


@app.command("atmosphere")
def atmosphere_command(
    range_: Annotated[
        str, typer.Option("--range", help="Path length(s), comma-separated, e.g. 1km,2km,5km.")
    ],
    band: BandOption = None,
    extinction: ExtinctionOption = None,
    obscurant: ObscurantOption = None,
    visibility: VisibilityOption = None,
    visibility_convention: ConventionOption = None,
    output_format: FormatOption = "table",
) -> None:
    """Transmittance (7.3), SNR (7.7) and the Table 7.2 description of a path."""
    _choice(output_format, FORMATS, "--format")
    lengths = [parse_quantity(part, "length", "--range") for part in range_.split(",")]
    if not all(r >= 0 for r in lengths):
        raise ValueError(f"--range must be >= 0; got {range_!r}")
    path = _path(
        extinction, obscurant, visibility, visibility_convention, _band(band) if band else None
    )
    if not path:
        raise ValueError("give the path's extinction: --extinction, --obscurant or --visibility")
    gamma = path["extinction_np_per_m"]
    rows = []
    for r in lengths:
        tau = float(atmosphere.transmittance(gamma, r))
        snr = float(atmosphere.snr_from_transmittance(tau))
        rows.append(
            {
                "range_m": r,
                "transmittance": tau,
                "snr_db": snr if math.isfinite(snr) else None,
                "snr": "+inf"
                if snr == math.inf
                else ("-inf" if snr == -math.inf else f"{snr:.4g}"),
            }
        )
    report = {"path": path, "rows": rows}
    if output_format == "json":
        typer.echo(json.dumps(report, indent=2))
        return
    if output_format == "csv":
        buffer = io.StringIO()
        writer = csv.DictWriter(
            buffer,
            fieldnames=["range_m", "transmittance", "snr_db"],
            lineterminator="\n",
            extrasaction="ignore",
        )
        writer.writeheader()
        writer.writerows(rows)
        typer.echo(buffer.getvalue(), nl=False)
        return
    lines = [
        f"extinction {path['extinction_np_per_km']:.4g} Np/km "
        f"({np_per_km_to_db_per_km(path['extinction_np_per_km']):.4g} dB/km): {path['term']}, "
        f"visual range {path['visual_range']} (Table 7.2); {path['source']}",
        "",
        f"{'range [m]':>12}  {'τ':>10}  {'SNR [dB]':>10}",
    ]
    lines += [
        f"{row['range_m']:>12,.0f}  {row['transmittance']:>10.4g}  {row['snr']:>10}" for row in rows
    ]
    typer.echo("\n".join(lines))


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


def _json_number(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def _render_rows(rows: list[dict[str, Any]], output_format: str) -> str:
    if output_format == "json":
        clean = [{k: _json_number(v) for k, v in row.items()} for row in rows]
        return json.dumps({"targets": clean}, indent=2) + "\n"
    if output_format == "csv":
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        return buffer.getvalue()
    header = (
        f"{'#':>3} {'box x,y,w,h':<18}{'clutter':>9}{'SCR+':>8}{'SCR-':>8} {'region':<7}"
        f"{'cycles':>7}{'P(det)':>8}{'aspect':>7}{'σ/mean':>8}{'edges':>7}{'contrast':>9}"
    )
    lines = [header, "-" * len(header)]
    for row in rows:
        lines.append(
            f"{row['target']:>3} {row['box']:<18}{row['clutter']:>9.4g}{row['scr_positive']:>8.3g}"
            f"{row['scr_negative']:>8.3g} {row['region']:<7}{row['cycles']:>7.3g}"
            f"{row['p_detection']:>8.3f}{row['aspect']:>7.2f}{row['std_over_mean']:>8.3f}"
            f"{row['edge_strength']:>7.2f}{row['contrast']:>9.3f}"
        )
    return "\n".join(lines) + "\n"


def _scenario_path(scenario: str | None) -> Any:
    if scenario is not None:
        return load_scenario(scenario)
    default = resources.files("targetacq").joinpath("examples").joinpath(DEFAULT_EXAMPLE)
    with resources.as_file(default) as path:
        return load_scenario(path)


ScenarioArgument = Annotated[
    str | None,
    typer.Argument(metavar="SCENARIO", help="Scenario TOML file (default: the bundled example)."),
]


@app.command()
def validate(scenario: Annotated[str, typer.Argument(metavar="SCENARIO")]) -> None:
    """Check a scenario file without running it."""
    loaded = load_scenario(scenario)
    times = loaded.time.times()
    typer.echo(
        f"{scenario}: valid — {len(loaded.sensors)} sensor(s), {len(loaded.targets)} target(s), "
        f"{times.size} time(s) from {times[0]:g} s to {times[-1]:g} s"
    )


@app.command()
def evaluate(
    scenario: ScenarioArgument = None,
    out: Annotated[
        str | None, typer.Option(help="Write every sensor-target-time row: .csv, .json, .parquet.")
    ] = None,
    output_format: FormatOption = "table",
) -> None:
    """Evaluate all sensors x targets x times of a scenario; print the peak fused
    probabilities per target (and write the full table with --out)."""
    _choice(output_format, FORMATS, "--format")
    loaded = _scenario_path(scenario)
    results = ModelChain(loaded).evaluate()
    if out is not None:
        results.write(out)
    ds = results.dataset
    rows = []
    for target in ds["target"].values:
        row: dict[str, Any] = {"target": str(target)}
        for task in ("detection", "recognition", "identification"):
            series = ds[f"fused_{task}"].sel(target=target).values
            best = int(np.argmax(series))
            row[f"peak_{task}"] = float(series[best])
            row[f"at_{task}_s"] = float(ds["time"][best])
        row["in_view_steps"] = int(ds["in_view"].sel(target=target).any("sensor").sum())
        rows.append(row)
    if output_format == "table":
        lines = [
            f"{loaded.name or 'scenario'}: {len(loaded.sensors)} sensor(s), "
            f"{len(loaded.targets)} target(s), {ds.sizes['time']} time(s); peak fused "
            "probability over time (and when)",
            "",
            f"{'target':<16}{'detection':>18}{'recognition':>18}{'identification':>18}"
            f"{'in view':>9}",
        ]
        for row in rows:
            cells = "".join(
                f"{row[f'peak_{k}']:>9.3f} @{row[f'at_{k}_s']:>6.0f} s"
                for k in ("detection", "recognition", "identification")
            )
            lines.append(f"{row['target']:<16}{cells}{row['in_view_steps']:>9}")
        if out is not None:
            lines += ["", f"wrote {out}"]
        typer.echo("\n".join(lines))
    else:
        typer.echo(_render_rows(rows, output_format), nl=False)


@app.command()
def simulate(
    scenario: Annotated[str, typer.Argument(metavar="SCENARIO")],
    duration: Annotated[str, typer.Option(help="Simulated time, e.g. 60s.")] = "60 s",
    step: Annotated[str, typer.Option(help="Time step, e.g. 0.1s.")] = "0.1 s",
    seed: Annotated[int, typer.Option(help="Seed (>= 0); same seed, same outcomes.")] = 0,
    runs: Annotated[int, typer.Option(help="Independent runs.")] = 1000,
    output_format: FormatOption = "table",
) -> None:
    """Random acquisition over time (field-of-view search model): per target, the fraction of
    runs with a detection / recognition / identification and the distribution of its first time."""
    _choice(output_format, FORMATS, "--format")
    t_total = parse_quantity(duration, "time", "--duration")
    dt = parse_quantity(step, "time", "--step")
    if not t_total > 0 or not dt > 0:
        raise ValueError("--duration and --step must be > 0")
    if runs < 1:
        raise ValueError(f"--runs must be >= 1; got {runs}")
    if seed < 0:
        raise ValueError(f"--seed must be >= 0; got {seed}")
    chain = ModelChain(load_scenario(scenario))
    from rich.progress import Progress

    with Progress(
        transient=True, disable=not sys.stderr.isatty(), console=_stderr_console()
    ) as bar:
        task = bar.add_task("simulating", total=runs)
        result = simulate_runs(
            chain,
            t_total,
            dt,
            runs=runs,
            seed=seed,
            progress=lambda n: bar.advance(task, n),
        )
    summary = result.summary()
    if output_format == "table":
        lines = [
            f"{runs} runs, {t_total:g} s in steps of {dt:g} s, seed {seed}; first times over "
            "runs (sensor-level fusion); inf: not reached by that share of runs",
            "",
            f"{'target':<16}{'task':<16}{'fraction':>9}{'t10 [s]':>9}{'t50 [s]':>9}{'t90 [s]':>9}",
        ]
        for _, row in summary.iterrows():
            lines.append(
                f"{row['target']:<16}{row['task']:<16}{row['fraction']:>9.3f}"
                f"{row['t10_s']:>9.3g}{row['t50_s']:>9.3g}{row['t90_s']:>9.3g}"
            )
        typer.echo("\n".join(lines))
    else:
        rows = [dict(r) for r in summary.to_dict(orient="records")]
        typer.echo(_render_rows(rows, output_format), nl=False)


def _stderr_console() -> Any:
    from rich.console import Console

    return Console(stderr=True)


_PASS_THROUGH = {"allow_extra_args": True, "ignore_unknown_options": True}


def _dri_params(args: list[str]) -> tuple[dict[str, Any], set[str]]:
    """Parse sensor/target/path options with the `dri` command's own parser.

    Returns the parameters and the names of those given on the command line.
    """
    group = typer.main.get_command(app)
    command = group.commands["dri"]  # type: ignore[attr-defined]
    context = command.make_context("dri", list(args))
    defaults = {p.name: p.default for p in command.params}
    given = {name for name, value in context.params.items() if value != defaults.get(name)}
    return dict(context.params), given


def _title(setup: _Setup) -> str:
    sensor = setup.sensor
    if "pitch_m" in sensor:
        pitch_um, focal_mm = sensor["pitch_m"] * 1e6, sensor["focal_length_m"] * 1e3
        optics_text = f"{pitch_um:.3g} µm pitch, {focal_mm:.4g} mm focal length"
    elif "hfov_rad" in sensor:
        optics_text = f"{math.degrees(sensor['hfov_rad']):.3g}° over {sensor['pixels']:.0f} pixels"
    else:
        optics_text = "IFOV given"
    return (
        f"IFOV {setup.ifov * 1e3:.4g} mrad ({optics_text}) — target critical dimension "
        f"{setup.critical_dimension:.3g} m"
    )


def _performance(setup: _Setup, max_range: str | None, probabilities: list[float]) -> Any:
    if max_range is not None:
        r_max = parse_quantity(max_range, "length", "--max-range")
        if not r_max > 0:
            raise ValueError(f"--max-range must be > 0; got {max_range!r}")
    else:
        reach = ranges.dri_ranges(
            setup.critical_dimension,
            setup.ifov,
            setup.criterion,
            probability=min(probabilities),
            transform=setup.transform,
            **setup.optics,
            **setup.clutter,
            **setup.options,
        )
        finite = [float(r) for r in reach.values() if math.isfinite(float(r))]
        r_max = 1.3 * max(finite) if finite else 10e3
    grid = [r_max * (k + 1) / 400 for k in range(400)]
    return ranges.range_performance(grid, {"this sensor": setup.case()}, probabilities)


@app.command(context_settings=_PASS_THROUGH)
def plot(
    context: typer.Context,
    kind: Annotated[str, typer.Argument(help=f"Figure: {', '.join(PLOT_KINDS)}.")],
    out: Annotated[str, typer.Option(help="Output file, .png or .svg.")],
    max_range: Annotated[
        str | None, typer.Option(help="Largest range on the axis, e.g. 8km (default: automatic).")
    ] = None,
    level: Annotated[
        str, typer.Option(help="atmosphere: Table 7.1 level, low|nominal|high.")
    ] = "nominal",
    title: Annotated[str | None, typer.Option(help="Figure title.")] = None,
) -> None:
    """Draw a figure. `curves` takes every sensor, target and path option of `targetacq dri`
    (and --probability for the marked DRI points); `transforms` takes --criterion or --n50;
    `atmosphere` takes --band."""
    _choice(kind, PLOT_KINDS, "plot kind")
    params, given = _dri_params(context.args)
    allowed = {
        "curves": None,
        "transforms": {"criterion", "n50"},
        "atmosphere": {"band"},
    }[kind]
    if allowed is not None and given - allowed:
        unused = ", ".join("--" + name.replace("_", "-") for name in sorted(given - allowed))
        raise ValueError(f"plot {kind} does not use {unused}")
    if kind == "curves":
        if "probability" not in given:
            params["probability"] = "0.5,0.8,0.95"
        setup = _setup(**{k: v for k, v in params.items() if k != "output_format"})
        performance = _performance(setup, max_range, setup.probabilities)
        fig = plot_range_performance(performance, title=title or _title(setup))
    elif kind == "transforms":
        crit = (
            _user_criterion(params["n50"])
            if params["n50"]
            else get_criterion(_choice(params["criterion"], CRITERIA, "--criterion"))
        )
        fig = plot_transforms(crit, title=title)
    else:
        r_max = 10e3 if max_range is None else parse_quantity(max_range, "length", "--max-range")
        _choice(level, EXTINCTION_LEVELS, "--level")
        band_value = _band(params["band"]) if params["band"] else BANDS["lwir"]
        fig = plot_atmosphere(band_value, r_max, level, title=title)
    written = save_figure(fig, out)
    typer.echo(f"wrote {written}")


@app.command(context_settings=_PASS_THROUGH)
def report(
    context: typer.Context,
    out: Annotated[str, typer.Option(help="Output file, .html.")],
    max_range: Annotated[
        str | None, typer.Option(help="Largest range of the curves, e.g. 8km (default: automatic).")
    ] = None,
    title: Annotated[str | None, typer.Option(help="Report title.")] = None,
) -> None:
    """Write a self-contained HTML report: inputs, model choices with sources, the DRI table at
    50 / 80 / 95 % and the figures. Takes every sensor, target and path option of
    `targetacq dri`."""
    params, given = _dri_params(context.args)
    if "probability" not in given:
        params["probability"] = "0.5,0.8,0.95"
    params.pop("output_format")
    setup = _setup(**params)
    if not setup.criterion.gives_probabilities:
        raise ValueError("the report needs a criterion with probabilities (not en62676-4)")
    performance = _performance(setup, max_range, setup.probabilities)
    heading = title or _title(setup)
    figures = {"Range performance": plot_range_performance(performance, title=heading)}
    figures["Transforms"] = plot_transforms(setup.criterion)
    if setup.path and params["band"]:
        figures["Atmosphere"] = plot_atmosphere(_band(params["band"]))
    page = render_report(
        performance, _report_sections(setup), figures, title=heading, version=__version__
    )
    written = write_report(out, page)
    typer.echo(f"wrote {written}")


def _report_sections(setup: _Setup) -> dict[str, dict[str, str]]:
    crit = setup.criterion
    sensor = {
        "IFOV": f"{setup.ifov * 1e3:.4g} mrad",
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
    target = {"critical dimension": f"{setup.critical_dimension:.4g} m (smallest side seen, §3.2)"}
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
            "noise model": f"{setup.noise_model}: {NOISE_MODELS[setup.noise_model].source}",
        }
        if setup.path
        else {"atmosphere": "none (geometry, clutter and optics only)"}
    )
    n50s = ", ".join(f"{task} {crit.threshold(task):g}" for task in crit.tasks)
    model = {
        "criterion": f"{crit.name}: N50 {n50s} cycles ({crit.source})",
        "transform": f"{setup.transform}: {TRANSFORMS[setup.transform].source}"
        + "".join(f"; {k} = {v}" for k, v in setup.options.items()),
        "clutter": "detection from Table 3.5 (Schmieder–Weathersby) by SCR region; recognition "
        "and identification do not depend on clutter (§3.8)"
        if setup.clutter
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


def _render(report: dict[str, Any], output_format: str) -> str:
    rows = report["ranges"]
    if output_format == "json":
        return json.dumps(report, indent=2) + "\n"
    if output_format == "csv":
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        return buffer.getvalue()
    sensor = report["sensor"]
    limit = "sampling" if math.isclose(sensor["cycle_rad"], 2 * sensor["ifov_rad"]) else "optics"
    lines = [
        f"criterion {report['criterion']}"
        + (f", transform {report['transform']}" if report["transform"] else "")
        + "".join(f", {k} {v}" for k, v in report["options"].items()),
        f"sensor: IFOV {sensor['ifov_rad'] * 1e3:.4g} mrad, resolvable cycle "
        f"{sensor['cycle_rad'] * 1e3:.4g} mrad ({limit}-limited)",
        f"target: critical dimension {report['target']['critical_dimension_m']:.4g} m"
        + _scene_line(report["target"]),
    ]
    if report["path"]:
        path = report["path"]
        lines.append(
            f"path: extinction {path['extinction_np_per_km']:.4g} Np/km ({path['term']}, visual "
            f"range {path['visual_range']}; {path['source']}), noise model {report['noise_model']}"
        )
    lines.append("")
    unit = rows[0]["threshold_unit"]
    header = f"{'task':<16}{'P':>6}  {'N50 [' + unit + ']':>18}  {'range [m]':>12}"
    lines += [header, "-" * len(header)]
    for row in rows:
        p = "-" if row["probability"] is None else f"{row['probability']:.2f}"
        if not row["reached"]:
            r = "not reached"
        elif row["range_m"] is None:
            r = "any"
        else:
            r = f"{row['range_m']:,.0f}"
        lines.append(f"{row['task']:<16}{p:>6}  {row['threshold']:>18.4g}  {r:>12}")
    return "\n".join(lines) + "\n"


def _scene_line(target: dict[str, Any]) -> str:
    parts = []
    if "contrast_w_per_m2" in target:
        parts.append(f"contrast {target['contrast_w_per_m2']:.4g} W/m²")
    if "scr" in target:
        parts.append(f"SCR {target['scr']:.4g}")
    if "region" in target:
        parts.append(f"{target['region']} clutter")
    return "; " + ", ".join(parts) if parts else ""


def _one_line(message: str) -> str:
    return " ".join(str(message).split())


def main(argv: list[str] | None = None) -> None:
    """Entry point: run the app; bad input → one line on stderr, exit status 2."""
    try:
        code = app(args=argv, prog_name="targetacq", standalone_mode=False)
    except typer.Abort:
        sys.stderr.write("targetacq: aborted\n")
        sys.exit(1)
    except typer.TyperException as error:  # usage errors: unknown option, missing value, ...
        message = error.format_message()
        if type(error).__name__ == "NoArgsIsHelpError":
            sys.stderr.write(message + "\n")
        else:
            sys.stderr.write(f"targetacq: error: {_one_line(message)}\n")
        sys.exit(2)
    except (ValueError, KeyError, TypeError) as error:
        sys.stderr.write(f"targetacq: error: {_one_line(str(error))}\n")
        sys.exit(2)
    sys.exit(code if isinstance(code, int) else 0)


if __name__ == "__main__":  # pragma: no cover
    main()
