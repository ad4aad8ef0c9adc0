"""The `dri` and `atmosphere` commands: ranges for a sensor and a target; a path."""

from __future__ import annotations

import math
from typing import Annotated, Any

import typer

from targetacq import atmosphere
from targetacq.acquisition import ACQUISITION_SEMANTICS
from targetacq.atmosphere import np_per_km_to_db_per_km
from targetacq.cli import (
    FORMATS,
    BandOption,
    ConventionOption,
    ExtinctionOption,
    FormatOption,
    ObscurantOption,
    VisibilityOption,
    _csv,
    app,
)
from targetacq.criteria import CRITERIA
from targetacq.noise import NOISE_MODELS
from targetacq.outputs import json_text
from targetacq.services.range_case import (
    dri_report,
    option_band,
    option_choice,
    option_path,
    option_quantity,
    range_setup,
)
from targetacq.transforms import C2NVEO_BOUNDS, CLUTTER_REGIONS, TRANSFORMS


@app.command()
def dri(
    pitch: Annotated[str | None, typer.Option(help="Pixel pitch, e.g. 17um.")] = None,
    focal_length: Annotated[str | None, typer.Option(help="Focal length, e.g. 75mm.")] = None,
    ifov: Annotated[str | None, typer.Option(help="Pixel IFOV, e.g. 0.227mrad.")] = None,
    hfov: Annotated[str | None, typer.Option(help="Horizontal field of view, e.g. 12deg.")] = None,
    pixels: Annotated[int | None, typer.Option(help="Pixels across --hfov, e.g. 640.")] = None,
    projection: Annotated[
        str | None,
        typer.Option(
            help="How --hfov over --pixels gives the IFOV: angular (HFOV / pixels, datasheets; "
            "the default) or rectilinear (2 tan(HFOV/2) / pixels)."
        ),
    ] = None,
    pixel_density: Annotated[
        str | None,
        typer.Option(
            help="EN 62676-4 pixel density from --hfov: plane (scene width 2R tan(HFOV/2), the "
            "default) or arc (R · HFOV)."
        ),
    ] = None,
    aperture: Annotated[
        str | None, typer.Option(help="Lens aperture diameter for diffraction, e.g. 75mm.")
    ] = None,
    f_number: Annotated[
        float | None, typer.Option(help="Lens F-number: aperture = focal length / F#.")
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
    transform: Annotated[
        str | None, typer.Option(help=f"Transform: {', '.join(TRANSFORMS)} (default ttpf).")
    ] = None,
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
    emissivity: Annotated[
        float | None, typer.Option(help="Target emissivity in [0, 1] (default 1).")
    ] = None,
    background_emissivity: Annotated[
        float | None, typer.Option(help="Background emissivity in [0, 1] (default 1).")
    ] = None,
    clutter_std: Annotated[
        str | None,
        typer.Option(help="Background temperature spread (clutter), e.g. 2K; gives the SCR."),
    ] = None,
    extinction: ExtinctionOption = None,
    obscurant: ObscurantOption = None,
    visibility: VisibilityOption = None,
    visibility_convention: ConventionOption = None,
    noise_model: Annotated[
        str | None,
        typer.Option(help=f"Noise model: {', '.join(NOISE_MODELS)} (default variance-sum)."),
    ] = None,
    netd: Annotated[
        str | None, typer.Option(help="Thermal camera's NETD, e.g. 50mK (needs --delta-t).")
    ] = None,
    netd_temperature: Annotated[
        str | None,
        typer.Option(
            help="Temperature at which the NETD is quoted, to turn the target and background "
            "temperatures into a ΔT (default 300K)."
        ),
    ] = None,
    delta_t: Annotated[
        str | None, typer.Option(help="Target-background temperature difference, e.g. 2K.")
    ] = None,
    nec: Annotated[
        float | None, typer.Option(help="TV camera's noise-equivalent contrast, e.g. 0.01.")
    ] = None,
    contrast: Annotated[
        float | None, typer.Option(help="Target contrast for --nec, e.g. 0.3.")
    ] = None,
    target_area: Annotated[
        str | None,
        typer.Option(help="Area of the target as seen, for its pixels (default: dimension²)."),
    ] = None,
    mrtd: Annotated[
        str | None,
        typer.Option(help="MRTD curve CSV (frequency [cycles/mrad], mrtd [K]); needs --delta-t."),
    ] = None,
    semantics: Annotated[
        str | None,
        typer.Option(
            help=f"Acquisition semantics: {', '.join(ACQUISITION_SEMANTICS)} (default nested)."
        ),
    ] = None,
    probability: Annotated[
        str | None,
        typer.Option(
            help="Probability, or several separated by commas, e.g. 0.5,0.8 (default 0.5)."
        ),
    ] = None,
    output_format: FormatOption = "table",
    example: Annotated[
        bool, typer.Option("--example", help="Use the bundled example camera and target.")
    ] = False,
) -> None:
    """Ranges at which each task (detection, recognition, identification) reaches a probability."""
    option_choice(output_format, FORMATS, "--format")
    params = dict(locals())
    params.pop("output_format")
    setup = range_setup(**params, default_probability="0.5")
    typer.echo(_render(dri_report(setup), output_format), nl=False)


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
    option_choice(output_format, FORMATS, "--format")
    lengths = [
        option_quantity(part, "length", "--range", zero_allowed=True) for part in range_.split(",")
    ]
    band_limits = option_band(band) if band else None
    path = option_path(extinction, obscurant, visibility, visibility_convention, band_limits)
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
                "snr_db": snr,
                "snr": "+inf"
                if snr == math.inf
                else ("-inf" if snr == -math.inf else f"{snr:.4g}"),
            }
        )
    report = {"path": path, "rows": rows}
    if output_format == "json":
        typer.echo(json_text(report))
        return
    if output_format == "csv":
        typer.echo(_csv(rows, ["range_m", "transmittance", "snr_db"]), nl=False)
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


def _render(report: dict[str, Any], output_format: str) -> str:
    rows = report["ranges"]
    if output_format == "json":
        return json_text(report) + "\n"
    if output_format == "csv":
        return _csv(rows)
    sensor = report["sensor"]
    limit = "sampling" if math.isclose(sensor["cycle_rad"], 2 * sensor["ifov_rad"]) else "optics"
    lines = [
        f"criterion {report['criterion']}"
        + (f", transform {report['transform']}" if report["transform"] else "")
        + "".join(f", {k} {v}" for k, v in report["options"].items()),
        _fov_line(sensor) + f"IFOV {sensor['ifov_rad'] * 1e3:.4g} mrad, resolvable cycle "
        f"{sensor['cycle_rad'] * 1e3:.4g} mrad ({limit}-limited)",
        f"target: critical dimension {report['target']['critical_dimension_m']:.4g} m"
        + _scene_line(report["target"]),
    ]
    target = report["target"]
    if report["resolution_model"] == "mrtd":
        lines.append(
            f"resolution: MRTD-limited, ΔT {target['delta_t_k']:.4g} K, curve cut-off "
            f"{target['mrtd_cutoff_cycles_per_mrad']:.4g} cycles/mrad"
        )
    if "noise_equivalent_contrast" in target:
        lines.append(
            f"sensor noise: noise-equivalent contrast {target['noise_equivalent_contrast']:.4g} "
            f"(target contrast {target.get('delta_t_k', target.get('contrast')):.4g}), "
            f"noise model {report['noise_model']}, semantics {report['semantics']}"
        )
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
        elif math.isinf(row["range_m"]):
            r = "any"
        else:
            r = f"{row['range_m']:,.0f}"
        lines.append(f"{row['task']:<16}{p:>6}  {row['threshold']:>18.4g}  {r:>12}")
    return "\n".join(lines) + "\n"


def _fov_line(sensor: dict[str, Any]) -> str:
    if "hfov_rad" not in sensor:
        return "sensor: "
    how = sensor.get("pixel_density") and f"pixel density {sensor['pixel_density']}"
    return (
        f"sensor: field of view {math.degrees(sensor['hfov_rad']):.4g}° × "
        f"{sensor['pixels']:.0f} pixels ({how or sensor['projection']}) → "
    )


def _scene_line(target: dict[str, Any]) -> str:
    parts = []
    if "contrast_w_per_m2" in target:
        parts.append(f"contrast {target['contrast_w_per_m2']:.4g} W/m²")
    if "scr" in target:
        parts.append(f"SCR {target['scr']:.4g}")
    if "region" in target:
        parts.append(f"{target['region']} clutter")
    return "; " + ", ".join(parts) if parts else ""
