"""The `dri` and `atmosphere` commands: ranges for a sensor and a target; a path."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any

import typer
import typer.main

from targetacq import atmosphere, optics, ranges
from targetacq.acquisition import ACQUISITION_SEMANTICS
from targetacq.atmosphere import (
    EXTINCTION_LEVELS,
    OBSCURANTS,
    VISIBILITY_CONVENTIONS,
    np_per_km_to_db_per_km,
)
from targetacq.bands import band_name, parse_band
from targetacq.cli import (
    _SI_SUFFIX,
    FORMATS,
    BandOption,
    ConventionOption,
    ExtinctionOption,
    FormatOption,
    ObscurantOption,
    VisibilityOption,
    _choice,
    _csv,
    app,
)
from targetacq.core.cases import RangeCase
from targetacq.criteria import CRITERIA, Criterion, get_criterion
from targetacq.limits import (
    check_count,
    check_length,
    check_temperature,
    check_temperature_difference,
)
from targetacq.noise import NOISE_MODELS
from targetacq.outputs import json_text
from targetacq.scene import scene_signature
from targetacq.tables import load_table
from targetacq.transforms import C2NVEO_BOUNDS, CLUTTER_REGIONS, TRANSFORMS
from targetacq.units import parse_quantity


def _example_camera() -> dict[str, str]:
    table = load_table("example_camera")
    return {
        quantity: f"{value} {unit}".strip()
        for quantity, value, unit in zip(
            table.column("quantity"), table.column("value"), table.column("unit"), strict=True
        )
    }


def _quantity(text: str, kind: str, option: str, *, zero_allowed: bool = False) -> float:
    """The option's quantity in SI units: finite (:func:`parse_quantity`), > 0 (or >= 0), and a
    length within ±``limits.MAX_LENGTH`` (:func:`targetacq.limits.check_length`)."""
    value = parse_quantity(text, kind, option)
    if not (value >= 0 if zero_allowed else value > 0):
        raise ValueError(f"{option} must be {'>= 0' if zero_allowed else '> 0'}; got {text!r}")
    if kind == "length":
        check_length(option, value)
    return value


def _temperature(text: str, option: str) -> float:
    """A temperature option [K] (:func:`targetacq.limits.check_temperature`)."""
    return check_temperature(option, parse_quantity(text, "temperature", option))


def _temperature_difference(text: str, option: str, *, signed: bool = False) -> float:
    """A temperature difference option [K]
    (:func:`targetacq.limits.check_temperature_difference`)."""
    value = parse_quantity(text, "temperature difference", option)
    return check_temperature_difference(option, value, signed)


def _half_turn_angle(text: str, option: str) -> float:
    """An angle of view option [rad], in (0°, 180°): a lens sees less than a half-turn."""
    value = parse_quantity(text, "angle", option)
    if not 0 < value < math.pi:
        raise ValueError(f"{option} must be in (0, 180) deg; got {text!r}")
    return value


def _number(value: float, option: str, valid: str) -> float:
    """A plain number option, finite and ``valid``: "> 0", ">= 0", "in [0, 1]" or "finite"."""
    ok = (
        math.isfinite(value)
        and {
            "> 0": value > 0,
            ">= 0": value >= 0,
            "in [0, 1]": 0 <= value <= 1,
            "finite": True,
        }[valid]
    )
    if not ok:
        # an interval excludes infinities by itself; an inequality needs saying finite
        condition = valid if valid in ("finite", "in [0, 1]") else f"finite and {valid}"
        raise ValueError(f"{option} must be {condition}; got {value:g}")
    return value


def _probabilities(text: str) -> list[float]:
    values = []
    for part in text.split(","):
        try:
            p = float(part)
        except ValueError as error:
            raise ValueError(f"--probability: {part!r} is not a number in (0, 1)") from error
        if not 0 < p < 1:  # NaN fails too
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
    # A harder task needs more cycles (every published set, Johnson's first): equal or
    # decreasing N50s are a slip, and would make recognition likelier than detection.
    if not values[0] < values[1] < values[2]:
        raise ValueError(
            "--n50 must increase: detection < recognition < identification; got "
            + ", ".join(f"{v:g}" for v in values)
        )
    return get_criterion(
        dict(zip(("detection", "recognition", "identification"), values, strict=True))
    )


def _sensor_ifov(
    pitch: str | None,
    focal_length: str | None,
    ifov: str | None,
    hfov: str | None,
    pixels: int | None,
    projection: str | None,
) -> tuple[float, dict[str, Any]]:
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
    if projection is not None:
        _choice(projection, optics.FIELD_OF_VIEW_PROJECTIONS, "--projection")
        if not ways[2]:
            raise ValueError("--projection applies to --hfov and --pixels")
    if ways[0]:
        if pitch is None or focal_length is None:
            raise ValueError("--pitch and --focal-length go together")
        p = _quantity(pitch, "length", "--pitch")
        f = _quantity(focal_length, "length", "--focal-length")
        value = float(optics.ifov(p, f))
        if not 0 < value < math.pi:  # 1e-300 m over 1e300 m underflows to 0
            raise ValueError(
                f"--pitch {pitch} over --focal-length {focal_length} gives an IFOV of "
                f"{value:g} rad, outside (0, π)"
            )
        return value, {"pitch_m": p, "focal_length_m": f}
    if ways[1]:
        assert ifov is not None
        return _half_turn_angle(ifov, "--ifov"), {}
    if hfov is None or pixels is None:
        raise ValueError("--hfov and --pixels go together")
    fov = _half_turn_angle(hfov, "--hfov")
    check_count("--pixels", pixels)
    projection = projection or "angular"
    value = float(optics.ifov_from_field_of_view(fov, pixels, projection))
    return value, {"hfov_rad": fov, "pixels": float(pixels), "projection": projection}


PIXEL_DENSITY_DEFINITIONS = {
    "plane": "rectilinear",  # EN 62676-4: pixels across the scene width 2 R tan(HFOV/2)
    "arc": "angular",  # pixels across the arc R · HFOV
}
"""EN 62676-4 pixel density from a field of view: the definition → the projection it uses."""


def _sensor_noise(
    netd: str | None,
    netd_temperature: str | None,
    delta_t: str | None,
    nec: float | None,
    contrast: float | None,
    mrtd: str | None,
    scene: dict[str, Any],
    band: tuple[float, float] | None,
) -> dict[str, Any]:
    """RangeCase keywords of the sensor's noise and MRTD, from --netd/--delta-t, --nec/--contrast
    and --mrtd; a ΔT from the temperatures where --delta-t is not given."""
    from targetacq.radiometry import band_exitance_derivative

    if (nec is None) != (contrast is None):
        raise ValueError("--nec and --contrast go together (a TV camera's noise)")
    if nec is not None and (netd is not None or mrtd is not None):
        raise ValueError("--nec (a TV camera) and --netd or --mrtd (a thermal camera) exclude")
    if netd is None and mrtd is None:
        for option, value in (("--delta-t", delta_t), ("--netd-temperature", netd_temperature)):
            if value is not None:
                raise ValueError(f"{option} is used with --netd or --mrtd (a thermal camera)")
        if nec is None:
            return {}
        assert contrast is not None
        return {
            "contrast": _number(contrast, "--contrast", "finite"),
            "noise_equivalent_contrast": _number(nec, "--nec", ">= 0"),
        }
    if delta_t is not None:
        if "contrast_w_per_m2" in scene:
            raise ValueError(
                "give the target's contrast one way: --delta-t, or --target-temperature and "
                "--background-temperature"
            )
        if netd_temperature is not None:
            raise ValueError(
                "--netd-temperature converts the temperatures' contrast into a ΔT; with "
                "--delta-t it is not used"
            )
        dt = _temperature_difference(delta_t, "--delta-t", signed=True)
    elif "contrast_w_per_m2" in scene and band is not None:
        reference = _temperature(netd_temperature or "300K", "--netd-temperature")
        # The blackbody ΔT at the reference temperature that gives the same exitance contrast.
        dt = scene["contrast_w_per_m2"] / float(band_exitance_derivative(reference, band))
    else:
        raise ValueError(
            "--netd and --mrtd need the target's contrast: --delta-t (e.g. 2K), or "
            "--target-temperature and --background-temperature with --band"
        )
    out: dict[str, Any] = {"contrast": dt}
    if netd is not None:
        out["noise_equivalent_contrast"] = _temperature_difference(netd, "--netd")
    if mrtd is not None:
        from targetacq.mrtd import MrtdCurve

        try:
            out["mrtd"] = MrtdCurve.from_csv(mrtd)
        except ValueError as error:
            raise ValueError(f"--mrtd: {error}") from None
    return out


def _band(text: str) -> tuple[float, float]:
    """A named band, or "8-12um"-style limits, as (λ1, λ2) [m]."""
    return parse_band(text, "--band")


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
    weather: dict[str, Any] = {}
    if extinction is not None:
        weather["extinction"] = _quantity(
            extinction, "extinction", "--extinction", zero_allowed=True
        )
        source = f"--extinction {extinction}"
    elif obscurant is not None:
        if band is None:
            raise ValueError("--obscurant needs --band (Table 7.1 depends on the band)")
        name, _, level = obscurant.partition(":")
        _choice(name, OBSCURANTS, "--obscurant")
        level = level or "nominal"
        _choice(level, EXTINCTION_LEVELS, "--obscurant level")
        weather["obscurant"] = f"{name}:{level}"
        source = f"Table 7.1: {name}, {level}, {band_name(band)}"
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
        weather["visibility"] = _quantity(visibility, "length", "--visibility")
        weather["convention"] = convention
        source = f"visibility {visibility} ({convention})"
    else:
        return {}
    gamma = atmosphere.extinction_for_band(band, **weather)
    term, visual_range = atmosphere.extinction_term(gamma)
    return {
        "extinction_np_per_m": gamma,
        "extinction_np_per_km": gamma * 1e3,
        "term": term,
        "visual_range": visual_range,
        "source": source,
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
    emissivity: float | None,
    background_emissivity: float | None,
    band: tuple[float, float] | None,
) -> dict[str, Any]:
    """SCR or clutter region from --scr, --clutter, or temperatures with --clutter-std."""
    if sum(v is not None for v in (scr, region, clutter_std)) > 1:
        raise ValueError("give one of --scr, --clutter and --clutter-std")
    temperatures = (target_temperature, background_temperature)
    if any(t is not None for t in temperatures) and None in temperatures:
        raise ValueError("--target-temperature and --background-temperature go together")
    if target_temperature is None:
        for option, value in (
            ("--emissivity", emissivity),
            ("--background-emissivity", background_emissivity),
        ):
            if value is not None:
                raise ValueError(
                    f"{option} is used with --target-temperature and --background-temperature"
                )
    if scr is not None:
        return {"scr": _number(scr, "--scr", ">= 0")}
    if region is not None:
        return {"region": _choice(region, CLUTTER_REGIONS, "--clutter")}
    if target_temperature is None or background_temperature is None:
        if clutter_std is not None:
            raise ValueError(
                "--clutter-std needs --target-temperature and --background-temperature"
            )
        return {}
    if band is None:
        raise ValueError("temperatures need --band to compute the band exitance")
    t_t = _temperature(target_temperature, "--target-temperature")
    t_b = _temperature(background_temperature, "--background-temperature")
    eps_t = 1.0 if emissivity is None else _number(emissivity, "--emissivity", "in [0, 1]")
    eps_b = (
        1.0
        if background_emissivity is None
        else _number(background_emissivity, "--background-emissivity", "in [0, 1]")
    )
    sigma_t = None
    if clutter_std is not None:
        sigma_t = _temperature_difference(clutter_std, "--clutter-std")
    seen = scene_signature(
        band,
        t_t,
        t_b,
        target_emissivity=eps_t,
        background_emissivity=eps_b,
        clutter_std=sigma_t,
    )
    info: dict[str, Any] = {
        "target_temperature_k": t_t,
        "background_temperature_k": t_b,
        "contrast_w_per_m2": float(seen.contrast),
    }
    if seen.scr is not None:
        info["clutter_w_per_m2"] = float(seen.clutter)
        info["scr"] = float(seen.scr)
    return info


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
    _choice(output_format, FORMATS, "--format")
    params = dict(locals())
    params.pop("output_format")
    setup = _setup(**params, default_probability="0.5")
    typer.echo(_render(_dri_report(setup), output_format), nl=False)


@dataclass(frozen=True)
class _Setup:
    """Everything the dri, plot and report commands read from the sensor/target/path options:
    the range case, and for the output how the sensor, the path and the scene were given."""

    case: RangeCase
    sensor: dict[str, float]
    path: dict[str, Any]
    scene: dict[str, Any]
    probabilities: list[float]

    @property
    def criterion(self) -> Criterion:
        return get_criterion(self.case.criterion)

    @property
    def optics(self) -> dict[str, Any]:
        """The optics limits given (aperture, wavelength, blur_sigma) [SI]."""
        names = ("aperture", "wavelength", "blur_sigma")
        return {k: getattr(self.case, k) for k in names if getattr(self.case, k) is not None}

    @property
    def cycle(self) -> float:
        return float(self.case.cycle_angle)


def _setup(
    pitch: str | None,
    focal_length: str | None,
    ifov: str | None,
    hfov: str | None,
    pixels: int | None,
    projection: str | None,
    pixel_density: str | None,
    aperture: str | None,
    f_number: float | None,
    wavelength: str | None,
    blur: str | None,
    critical_dimension: str | None,
    criterion: str,
    n50: str | None,
    transform: str | None,
    bound: str | None,
    scr: float | None,
    clutter: str | None,
    band: str | None,
    target_temperature: str | None,
    background_temperature: str | None,
    emissivity: float | None,
    background_emissivity: float | None,
    clutter_std: str | None,
    extinction: str | None,
    obscurant: str | None,
    visibility: str | None,
    visibility_convention: str | None,
    noise_model: str | None,
    netd: str | None,
    netd_temperature: str | None,
    delta_t: str | None,
    nec: float | None,
    contrast: float | None,
    target_area: str | None,
    mrtd: str | None,
    semantics: str | None,
    probability: str | None,
    example: bool,
    *,
    default_probability: str,
) -> _Setup:
    """The range case and its description from the options of `dri` (also `plot curves` and
    `report`, whose ``default_probability`` differs); every option checked finite and in its
    domain, and every option that would be ignored refused, naming it."""
    if transform is not None:
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
    d = _quantity(critical_dimension, "length", "--critical-dimension")
    ifov_rad, sensor = _sensor_ifov(pitch, focal_length, ifov, hfov, pixels, projection)
    optics_kw: dict[str, Any] = {}
    if f_number is not None:
        if aperture is not None:
            raise ValueError("give --aperture or --f-number, not both")
        if "focal_length_m" not in sensor:
            raise ValueError("--f-number needs --focal-length (aperture = focal length / F#)")
        sensor["f_number"] = _number(f_number, "--f-number", "> 0")
        if wavelength is None:
            raise ValueError("--f-number gives the aperture for diffraction: give --wavelength")
    if (aperture is None and f_number is None) != (wavelength is None):
        raise ValueError("--aperture and --wavelength go together (diffraction limit)")
    if wavelength is not None:
        optics_kw["aperture"] = (
            sensor["focal_length_m"] / f_number
            if f_number is not None
            else _quantity(str(aperture), "length", "--aperture")
        )
        optics_kw["wavelength"] = _quantity(wavelength, "length", "--wavelength")
    if blur is not None:
        optics_kw["blur_sigma"] = parse_quantity(blur, "angle", "--blur")
        if not 0 <= optics_kw["blur_sigma"] < math.pi:
            raise ValueError(f"--blur must be in [0, 180) deg; got {blur!r}")
    if n50 is not None and criterion != "johnson":
        raise ValueError("give either --criterion or --n50, not both")
    crit = (
        _user_criterion(n50)
        if n50 is not None
        else get_criterion(_choice(criterion, CRITERIA, "--criterion"))
    )
    if not crit.gives_probabilities:
        # A pixel-density criterion gives thresholds, one range each: no probability, no
        # transform, no semantics, and pixel density counted its own way (--pixel-density).
        for option, value in (
            ("--probability", probability),
            ("--transform", transform),
            ("--semantics", semantics),
            ("--projection", projection),
        ):
            if value is not None:
                raise ValueError(
                    f"--criterion {crit.name} gives pixel-density thresholds; {option} does "
                    "not apply"
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
    if noise_model is not None:
        _choice(noise_model, NOISE_MODELS, "--noise-model")
    if semantics is not None:
        _choice(semantics, ACQUISITION_SEMANTICS, "--semantics")
    if pixel_density is not None:
        _choice(pixel_density, PIXEL_DENSITY_DEFINITIONS, "--pixel-density")
    if not crit.gives_probabilities and "hfov_rad" in sensor:
        # EN 62676-4 counts pixels across the scene, whatever the lens's own projection.
        density = pixel_density or "plane"
        ifov_rad = float(
            optics.ifov_from_field_of_view(
                sensor["hfov_rad"], pixels, PIXEL_DENSITY_DEFINITIONS[density]
            )
        )
        sensor["pixel_density"] = density
    elif pixel_density is not None:
        raise ValueError("--pixel-density applies to a pixel-density criterion with --hfov")
    noise_kw = _sensor_noise(
        netd, netd_temperature, delta_t, nec, contrast, mrtd, scene, band_limits_m
    )
    if target_area is not None:
        if "noise_equivalent_contrast" not in noise_kw:
            raise ValueError("--target-area is used with the sensor's noise (--netd or --nec)")
        noise_kw["target_area"] = _quantity(target_area, "area", "--target-area")
    case = RangeCase(
        d,
        ifov_rad,
        **optics_kw,
        **noise_kw,
        semantics=semantics or "nested",
        criterion=crit,
        transform=transform or "ttpf",
        options=options,
        extinction=path.get("extinction_np_per_m"),
        scr=scene.get("scr"),
        region=scene.get("region"),
        noise_model=noise_model or "variance-sum",
    )
    if noise_model is not None and not case.noisy:
        raise ValueError(
            "--noise-model applies to a noisy path or sensor: give --extinction, --obscurant, "
            "--visibility, --netd or --nec"
        )
    return _Setup(
        case=case,
        sensor=sensor,
        path=path,
        scene=scene,
        probabilities=_probabilities(default_probability if probability is None else probability),
    )


def _dri_report(setup: _Setup) -> dict[str, Any]:
    case, crit = setup.case, setup.criterion
    rows = []
    for p in setup.probabilities:
        for task, r in ranges.case_ranges(case, p).items():
            value = float(r)
            rows.append(
                {
                    "task": task,
                    "probability": p if crit.gives_probabilities else None,
                    "threshold": crit.threshold(task),
                    "threshold_unit": "cycles" if crit.gives_probabilities else "pixels/m",
                    # NaN: never reached (null in JSON); +inf: reached at any range ("inf")
                    "range_m": None if math.isnan(value) else value,
                    "reached": not math.isnan(value),
                }
            )
        if not crit.gives_probabilities:
            break
    return {
        "sensor": {
            "ifov_rad": case.ifov,
            "cycle_rad": setup.cycle,
            **setup.sensor,
            **{f"{k}_{_SI_SUFFIX[k]}": v for k, v in setup.optics.items()},
        },
        "target": {
            "critical_dimension_m": case.critical_dimension,
            **setup.scene,
            **_noise_report(case),
        },
        "path": setup.path,
        "criterion": crit.name,
        "criterion_kind": crit.kind,
        "transform": case.transform if crit.gives_probabilities else None,
        "options": case.options,
        "noise_model": case.noise_model if case.noisy else None,
        "semantics": case.semantics,
        "resolution_model": case.resolution_model,
        "ranges": rows,
    }


def _noise_report(case: RangeCase) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if case.contrast is not None:
        out[
            "delta_t_k"
            if case.mrtd is not None or case.noise_equivalent_contrast is None
            else "contrast"
        ] = float(case.contrast)
    if case.noise_equivalent_contrast is not None:
        out["noise_equivalent_contrast"] = float(case.noise_equivalent_contrast)
    if case.target_area is not None:
        out["target_area_m2"] = float(case.target_area)
    if case.mrtd is not None:
        out["mrtd_cutoff_cycles_per_mrad"] = case.mrtd.cutoff * 1e-3
    return out


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
    lengths = [
        _quantity(part, "length", "--range", zero_allowed=True) for part in range_.split(",")
    ]
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
