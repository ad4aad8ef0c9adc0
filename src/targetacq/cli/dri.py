"""The `dri` and `atmosphere` commands: ranges for a sensor and a target; a path."""

from __future__ import annotations

import math
from typing import Annotated, Any

import typer

from targetacq.cli import (
    FORMATS,
    BandOption,
    ConventionOption,
    ExtinctionOption,
    FormatOption,
    ObscurantOption,
    VisibilityOption,
    _csv,
    _model_line,
    app,
)
from targetacq.cli.options import range_case_options, uncertainty_options
from targetacq.cli.params import complete_names
from targetacq.io.files import json_text
from targetacq.physics import atmosphere, named_atmospheres
from targetacq.physics.atmosphere import np_per_km_to_db_per_km
from targetacq.run.atmosphere_options import named_path_description, option_named_path
from targetacq.run.option_table import option_lists, typed_options
from targetacq.run.range_options import (
    dri_report,
    option_band,
    option_choice,
    option_path,
    option_quantity,
    range_setup,
)
from targetacq.run.uncertainty import read_uncertainty, uncertainty_report


@app.command()
@uncertainty_options
@range_case_options
def dri(
    scenario: Annotated[
        str | None,
        typer.Argument(help="A scenario file: the ranges of every sensor-target pair."),
    ] = None,
    *,
    case_options: dict[str, Any],
    uncertainty_options: dict[str, Any],
    output_format: FormatOption = "table",
) -> None:
    """Ranges at which each task (detection, recognition, identification) reaches a probability.

    Any option may take a comma-separated list: then `dri` prints the ranges of every
    combination, as `targetacq sweep` does (same keys in JSON and CSV). Given a scenario file,
    the ranges of each of its sensor-target pairs, any sensor type (takes --probability only).

    With --uncertainty N, each range comes with its 5–95 % band over N samples of the N50s
    (±25 %, Sonesson Table 3.2) and the spreads given: --observer-spread, --netd-spread,
    --extinction-spread.

    Example: targetacq dri --pitch 17um --focal-length 50mm,75mm --critical-dimension 2.3m

    Example: targetacq dri --example --visibility 10km --uncertainty 500 --extinction-spread 20%
    """
    option_choice(output_format, FORMATS, "--format")
    uncertainty = read_uncertainty(uncertainty_options)
    if uncertainty is not None and (scenario is not None or option_lists(case_options)):
        raise ValueError(
            "--uncertainty takes one range case (the sensor, target and path options, one "
            "value each), not a scenario file or lists"
        )
    if uncertainty is not None:
        setup = range_setup(typed_options(case_options, "dri"), "0.5")
        typer.echo(_render(uncertainty_report(setup, uncertainty), output_format), nl=False)
        return
    if scenario is not None:
        typer.echo(_scenario_dri(scenario, case_options, output_format), nl=False)
        return
    if option_lists(case_options):
        from targetacq.cli.sweep import render_sweep, run_sweep

        ds = run_sweep(case_options, progress=False)
        typer.echo(render_sweep(ds, output_format), nl=False)
        return
    setup = range_setup(typed_options(case_options, "dri"), "0.5")
    typer.echo(_render(dri_report(setup), output_format), nl=False)


def _scenario_dri(path: str, case_options: dict[str, Any], output_format: str) -> str:
    """The DRI ranges of every sensor-target pair of a scenario, as ``targetacq report`` has
    them: every sensor type through the core (:func:`targetacq.core.pair_ranges.pair_performance`:
    each target moved away from the sensor along its start bearing, the sensor looking at it)."""
    from targetacq.cli.figures import _check_scenario_options
    from targetacq.reports.content import TERRAIN_NOT_TRACED, scenario_performance
    from targetacq.run.model_chain import ModelChain
    from targetacq.run.range_options import option_probabilities
    from targetacq.scenario.schema import load_scenario

    _check_scenario_options(case_options, "a scenario's dri", "--probability and --format")
    probabilities = option_probabilities(case_options.get("probability") or "0.5")
    chain = ModelChain(load_scenario(path))
    performance, _ = scenario_performance(chain, None, probabilities, axis=False)
    rows = [
        {
            "pair": str(r["case"]),
            "task": str(r["task"]),
            "probability": float(r["probability"]),
            "range_m": float(r["range_m"]) if r["reached"] else None,
        }
        for _, r in performance.dri.iterrows()
    ]
    note = TERRAIN_NOT_TRACED.strip() if chain.scenario.terrain is not None else None
    if output_format == "json":
        return json_text({"scenario": path, "ranges": rows, **({"note": note} if note else {})})
    if output_format == "csv":
        return _csv(rows)
    lines = [f"{path}: DRI ranges [m] of every sensor-target pair"]
    if note:
        lines.append(f"({note})")
    for r in rows:
        reach = "not reached" if r["range_m"] is None else f"{r['range_m']:,.0f}"
        lines.append(f"  {r['pair']:<28} {r['task']:<15} P={r['probability']:<5g} {reach}")
    if any(r["range_m"] is None for r in rows):
        lines.append(
            "(each target moved away from the sensor along its start bearing, its height kept: "
            "'not reached' where the probability stays below P at every slant range from the "
            "height between them outwards)"
        )
    return "\n".join(lines) + "\n"


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
    named_atmosphere: Annotated[
        str | None,
        typer.Option(
            "--atmosphere",
            help="Named model atmosphere (LOWTRAN7 table): "
            + ", ".join(named_atmospheres.ATMOSPHERES)
            + "; --visibility is then the aerosol's.",
            autocompletion=complete_names(named_atmospheres.ATMOSPHERES, separator=None),
        ),
    ] = None,
    aerosol: Annotated[
        str | None,
        typer.Option(
            help="Aerosol of the named atmosphere: " + ", ".join(named_atmospheres.AEROSOLS) + ".",
            autocompletion=complete_names(named_atmospheres.AEROSOLS, separator=None),
        ),
    ] = None,
    path_altitude: Annotated[
        str | None,
        typer.Option(help="Height of the horizontal path above sea level, e.g. 500m (named)."),
    ] = None,
    output_format: FormatOption = "table",
) -> None:
    """Transmittance (7.3), SNR (7.7) and the Table 7.2 description of a path; or, with
    --atmosphere/--aerosol, the band transmittance and optical depth of a horizontal path
    through a named atmosphere (LOWTRAN7 table, not Beer-Lambert in range).

    Example: targetacq atmosphere --range 1km,2km,5km --band lwir --obscurant haze

    Example: targetacq atmosphere --atmosphere tropical --aerosol rural --visibility 23km
    --band 8-12um --range 5km
    """
    option_choice(output_format, FORMATS, "--format")
    lengths = [
        option_quantity(part, "length", "--range", zero_allowed=True) for part in range_.split(",")
    ]
    band_limits = option_band(band) if band else None
    if named_atmosphere is not None or aerosol is not None or path_altitude is not None:
        given = [
            flag
            for flag, value in (
                ("--extinction", extinction),
                ("--obscurant", obscurant),
                ("--visibility-convention", visibility_convention),
            )
            if value is not None
        ]
        if given:
            raise ValueError(
                f"{' and '.join(given)} do not go with a named atmosphere (--atmosphere, "
                "--aerosol): its --visibility is the aerosol's meteorological range"
            )
        if band_limits is None:
            raise ValueError(
                "a named atmosphere needs --band: " + ", ".join(named_atmospheres.NAMED_BANDS)
            )
        named = option_named_path(named_atmosphere, aerosol, visibility, path_altitude)
        assert named is not None
        _echo_named(named, band_limits, lengths, output_format)
        return
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
                "optical_depth": float(gamma * r),
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
        typer.echo(_csv(rows, ["range_m", "transmittance", "optical_depth", "snr_db"]), nl=False)
        return
    lines = [
        f"extinction {path['extinction_np_per_km']:.4g} Np/km "
        f"({np_per_km_to_db_per_km(path['extinction_np_per_km']):.4g} dB/km): "
        f"{path['description']}; {path['source']}",
        "",
        f"{'range [m]':>12}  {'τ':>10}  {'SNR [dB]':>10}",
    ]
    lines += [
        f"{row['range_m']:>12,.0f}  {row['transmittance']:>10.4g}  {row['snr']:>10}" for row in rows
    ]
    typer.echo("\n".join(lines))


def _echo_named(
    named: Any, band: tuple[float, float], lengths: list[float], output_format: str
) -> None:
    """The band transmittance, optical depth and SNR (7.7) of a named path at each length."""
    path = named_path_description(named, band)
    rows = []
    for r in lengths:
        depth = float(named.optical_depth(r, band))
        snr = float(atmosphere.snr_from_optical_depth(depth))
        rows.append(
            {
                "range_m": r,
                "transmittance": math.exp(-depth),
                "optical_depth": depth,
                "snr_db": snr,
                "snr": "+inf" if snr == math.inf else f"{snr:.4g}",
            }
        )
    if output_format == "json":
        typer.echo(json_text({"path": path, "rows": rows}))
        return
    if output_format == "csv":
        typer.echo(_csv(rows, ["range_m", "transmittance", "optical_depth", "snr_db"]), nl=False)
        return
    lines = [
        f"{path['description']}, band {path['band']}: band-mean transmittance (Eq. 7.4) from "
        f"{path['source']}",
        "",
        f"{'range [m]':>12}  {'τ':>10}  {'−ln τ':>10}  {'SNR [dB]':>10}",
    ]
    lines += [
        f"{row['range_m']:>12,.0f}  {row['transmittance']:>10.4g}  {row['optical_depth']:>10.4g}"
        f"  {row['snr']:>10}"
        for row in rows
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
        _model_line(report),
        _fov_line(sensor) + f"IFOV {sensor['ifov_rad'] * 1e3:.4g} mrad, resolvable cycle "
        f"{sensor['cycle_rad'] * 1e3:.4g} mrad ({limit}-limited)",
        (
            f"target: critical dimension {report['target']['critical_dimension_m']:.4g} m"
            if report["target"]["critical_dimension_m"] is not None
            else "target: any size (the criterion counts pixels per metre of the scene)"
        )
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
    if report["path"] and report["path"].get("model") == "named":
        path = report["path"]
        lines.append(
            f"path: {path['description']}, band {path['band']} (named atmosphere, LOWTRAN7 "
            f"table), noise model {report['noise_model']}"
        )
    elif report["path"]:
        path = report["path"]
        lines.append(
            f"path: extinction {path['extinction_np_per_km']:.4g} Np/km ({path['description']}; "
            f"{path['source']}), noise model {report['noise_model']}"
        )
    band = report.get("uncertainty")
    if band is not None:
        spreads = ", ".join(
            f"{name} {value:.0%}" for name, value in band["spreads"].items() if value
        )
        lines.append(
            f"uncertainty: {band['samples']} samples (seed {band['seed']}), lognormal spreads "
            f"{spreads or 'none'}; 5–95 % band of each range"
        )
    lines.append("")
    unit = rows[0]["threshold_unit"]
    header = f"{'task':<16}{'P':>6}  {'N50 [' + unit + ']':>18}  {'range [m]':>12}"
    if band is not None:
        header += f"  {'5 % [m]':>12}  {'95 % [m]':>12}"
    lines += [header, "-" * len(header)]
    for row in rows:
        p = "-" if row["probability"] is None else f"{row['probability']:.2f}"
        line = (
            f"{row['task']:<16}{p:>6}  {row['threshold']:>18.4g}  {_range_text(row['range_m']):>12}"
        )
        if band is not None:
            line += (
                f"  {_range_text(row['range_p05_m']):>12}  {_range_text(row['range_p95_m']):>12}"
            )
        lines.append(line)
    return "\n".join(lines) + "\n"


def _range_text(value: float | None) -> str:
    """A range [m] in the table: "not reached" (None), "any" (+inf) or metres."""
    if value is None:
        return "not reached"
    return "any" if math.isinf(value) else f"{value:,.0f}"


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
