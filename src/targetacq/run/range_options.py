"""Analyst cases from options: the sensor, target, path and model of a DRI question.

One compiler turns the options of ``targetacq dri`` (and ``plot curves``, ``report``,
``sweep`` and ``design``; later the web explorer) into a :class:`targetacq.core.cases.RangeCase`
and a description of how each part was given. Values are text with units, as on the command line
(``pitch="17um"``), so every front end checks and reports them the same way: finite, in their
domain, no option silently ignored. The physics is in the kernels this calls.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from targetacq.acquisition.criteria import CRITERIA, Criterion, get_criterion
from targetacq.acquisition.path_noise import NOISE_MODELS, SNR_LAWS
from targetacq.acquisition.probabilities import ACQUISITION_SEMANTICS
from targetacq.acquisition.transforms import C2NVEO_BOUNDS, CLUTTER_REGIONS, TRANSFORMS
from targetacq.base.limits import (
    check_count,
    check_length,
    check_temperature,
    check_temperature_difference,
)
from targetacq.base.tables import load_table
from targetacq.base.units import parse_quantity
from targetacq.core import ranges
from targetacq.core.cases import RangeCase
from targetacq.physics import atmosphere, optics
from targetacq.physics.atmosphere import EXTINCTION_LEVELS, OBSCURANTS, VISIBILITY_CONVENTIONS
from targetacq.physics.bands import band_name, parse_band
from targetacq.physics.named_atmospheres import NAMED_BANDS, NamedBandPath
from targetacq.physics.radiometry import band_exitance_derivative
from targetacq.physics.targets import TARGETS
from targetacq.run.atmosphere_options import named_path_description, option_named_path
from targetacq.run.scene import scene_signature
from targetacq.run.ttp_options import TTP_OPTIONS, read_resolution_model, ttp_system

_SI_SUFFIX = {"aperture": "m", "wavelength": "m", "blur_sigma": "rad"}
"""The SI unit suffix of each optics limit's key in a report."""

__all__ = [
    "PIXEL_DENSITY_DEFINITIONS",
    "RangeOptions",
    "RangeReading",
    "RangeSetup",
    "dri_report",
    "option_band",
    "option_choice",
    "option_criterion",
    "option_path",
    "option_probabilities",
    "option_quantity",
    "range_case",
    "range_setup",
    "read_range_options",
    "stack_readings",
]


def option_choice(value: str, choices: Any, name: str) -> str:
    """``value`` if it is one of ``choices``, else a ``ValueError`` naming ``name`` and the
    choices."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(choices)}; got {value!r}")
    return value


def example_camera() -> dict[str, str]:
    table = load_table("example_camera")
    return {
        quantity: f"{value} {unit}".strip()
        for quantity, value, unit in zip(
            table.column("quantity"), table.column("value"), table.column("unit"), strict=True
        )
    }


def option_quantity(text: str, kind: str, option: str, *, zero_allowed: bool = False) -> float:
    """The option's quantity in SI units: finite (:func:`parse_quantity`), > 0 (or >= 0), and a
    length within ±``limits.MAX_LENGTH`` (:func:`targetacq.base.limits.check_length`)."""
    value = parse_quantity(text, kind, option)
    if not (value >= 0 if zero_allowed else value > 0):
        raise ValueError(f"{option} must be {'>= 0' if zero_allowed else '> 0'}; got {text!r}")
    if kind == "length":
        check_length(option, value)
    return value


def _temperature(text: str, option: str) -> float:
    """A temperature option [K] (:func:`targetacq.base.limits.check_temperature`)."""
    return check_temperature(option, parse_quantity(text, "temperature", option))


def _temperature_difference(text: str, option: str, *, signed: bool = False) -> float:
    """A temperature difference option [K]
    (:func:`targetacq.base.limits.check_temperature_difference`)."""
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


def option_probabilities(text: str) -> list[float]:
    """The probabilities of ``--probability`` text (comma-separated), each in (0, 1)."""
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


def option_criterion(text: str) -> Criterion:
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


def _sensor_reading(
    pitch: str | None,
    focal_length: str | None,
    ifov: str | None,
    hfov: str | None,
    pixels: int | None,
    projection: str | None,
) -> tuple[str, dict[str, float], dict[str, Any]]:
    """How the sensor's resolution is given ("lens", "ifov" or "fov"), its numbers [SI] and its
    description so far, every option checked on its own; the kernels run in
    :func:`_sensor_resolution`."""
    by_lens = pitch is not None or focal_length is not None
    ways = [by_lens, ifov is not None, hfov is not None or (pixels is not None and not by_lens)]
    if sum(ways) != 1:
        raise ValueError(
            "give the sensor's resolution one way: --pitch and --focal-length (with --pixels "
            "for the field of view, as a datasheet gives them), or --ifov, or --hfov and "
            "--pixels (or --example)"
        )
    if projection is not None:
        option_choice(projection, optics.FIELD_OF_VIEW_PROJECTIONS, "--projection")
        if not ways[2]:
            raise ValueError("--projection applies to --hfov and --pixels")
    if ways[0]:
        if pitch is None or focal_length is None:
            raise ValueError("--pitch and --focal-length go together")
        p = option_quantity(pitch, "length", "--pitch")
        f = option_quantity(focal_length, "length", "--focal-length")
        if pixels is None:
            return "lens", {"pitch": p, "focal_length": f}, {"pitch_m": p, "focal_length_m": f}
        check_count("--pixels", pixels)
        numbers = {"pitch": p, "focal_length": f, "pixels": float(pixels)}
        return "lens", numbers, {"pitch_m": p, "focal_length_m": f}
    if ways[1]:
        assert ifov is not None
        return "ifov", {"ifov": _half_turn_angle(ifov, "--ifov")}, {}
    if hfov is None or pixels is None:
        raise ValueError("--hfov and --pixels go together")
    fov = _half_turn_angle(hfov, "--hfov")
    check_count("--pixels", pixels)
    return "fov", {"hfov": fov, "pixels": float(pixels)}, {"hfov_rad": fov}


def _first_bad(bad: Any) -> int | None:
    """The flat index of the first true element of ``bad`` (one point's bool, or the points'
    array), or None if none is."""
    flat = np.ravel(bad)
    return int(np.argmax(flat)) if flat.any() else None


def _element(value: Any, index: int) -> Any:
    """Element ``index`` of a stacked value (the points' array), or the value of one point."""
    return np.ravel(value)[index] if isinstance(value, np.ndarray) else value


def _sensor_resolution(reading: RangeReading) -> tuple[Any, dict[str, Any]]:
    """The IFOV [rad] of read options and the sensor's description that comes with it (the
    field of view, the pixel density), from the optics kernels: once on the points' arrays
    where the reading is stacked. An IFOV outside (0, π) is refused naming the first point's
    options that give it."""
    numbers, settings = reading.numbers, reading.settings
    sensor: dict[str, Any] = {}
    way = settings["resolution"]
    if way == "ifov":
        value = numbers["ifov"]
    elif way == "lens":
        p, f = numbers["pitch"], numbers["focal_length"]
        value = optics.ifov(p, f)
        index = _first_bad(~((value > 0) & (value < math.pi)))
        if index is not None:  # 1e-300 m over 1e300 m underflows to 0
            texts = reading.texts
            raise ValueError(
                f"--pitch {_element(texts['pitch'], index)} over --focal-length "
                f"{_element(texts['focal_length'], index)} gives an IFOV of "
                f"{float(_element(value, index)):g} rad, outside (0, π)"
            )
        if "pixels" in numbers:
            # The datasheet's way: the field of view of the detector's width behind the lens,
            # Eq. (5.1), reported beside the IFOV (which the pitch and focal length fix).
            sensor["hfov_rad"] = optics.field_of_view(numbers["pixels"] * p, f)
            sensor["pixels"] = numbers["pixels"]
            sensor["projection"] = "rectilinear"
    else:
        sensor["pixels"] = numbers["pixels"]
        sensor["projection"] = settings["projection"]
        value = optics.ifov_from_field_of_view(
            numbers["hfov"], numbers["pixels"], settings["projection"]
        )
    if "f_number" in numbers:
        sensor["f_number"] = numbers["f_number"]
    density = settings["pixel_density"]
    if density is not None:
        # EN 62676-4 counts pixels across the scene, whatever the lens's own projection.
        fov = sensor.get("hfov_rad", numbers.get("hfov"))
        value = optics.ifov_from_field_of_view(
            fov, numbers["pixels"], PIXEL_DENSITY_DEFINITIONS[density]
        )
        sensor["pixel_density"] = density
    return _one_or_many(value), {k: _one_or_many(v) for k, v in sensor.items()}


def _one_or_many(value: Any) -> Any:
    """A float for one point (a NumPy scalar or 0-d array), the array for stacked points."""
    return float(value) if np.ndim(value) == 0 and not isinstance(value, str) else value


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
        from targetacq.physics.mrtd import MrtdCurve

        try:
            out["mrtd"] = MrtdCurve.from_csv(mrtd)
        except ValueError as error:
            raise ValueError(f"--mrtd: {error}") from None
    return out


def option_band(text: str) -> tuple[float, float]:
    """A named band, or "8-12um"-style limits, as (λ1, λ2) [m]."""
    return parse_band(text, "--band")


def option_path(
    extinction: str | None,
    obscurant: str | None,
    visibility: str | None,
    convention: str | None,
    band: tuple[float, float] | None,
) -> dict[str, Any]:
    """The path's extinction from one of --extinction, --obscurant, --visibility ({} if none,
    or ``--obscurant none``: a clear path)."""
    given = [v is not None for v in (extinction, obscurant, visibility)]
    if sum(given) > 1:
        raise ValueError("give one of --extinction, --obscurant and --visibility")
    if convention is not None and visibility is None:
        raise ValueError("--visibility-convention goes with --visibility")
    weather: dict[str, Any] = {}
    if extinction is not None:
        weather["extinction"] = option_quantity(
            extinction, "extinction", "--extinction", zero_allowed=True
        )
        source = f"--extinction {extinction}"
    elif obscurant == "none":
        return {}  # a clear path, e.g. one value of an --obscurant none,fog:low sweep
    elif obscurant is not None:
        if band is None:
            raise ValueError("--obscurant needs --band (Table 7.1 depends on the band)")
        name, _, level = obscurant.partition(":")
        option_choice(name, OBSCURANTS, "--obscurant")
        level = level or "nominal"
        option_choice(level, EXTINCTION_LEVELS, "--obscurant level")
        weather["obscurant"] = f"{name}:{level}"
        named = band_name_or_none(band) or f"{band[0] * 1e6:g}-{band[1] * 1e6:g} um"
        source = f"Table 7.1: {name}, {level}, {named}"
    elif visibility is not None:
        if band is not None and band_name_or_none(band) != "visible":
            raise ValueError(
                "--visibility gives the visible-band extinction; for an infrared --band give "
                "--extinction or --obscurant, or a named atmosphere (--atmosphere, --aerosol) "
                "whose --visibility is the aerosol's"
            )
        if convention is None:
            raise ValueError(
                "--visibility needs --visibility-convention koschmieder (2 % contrast, 3.912/V) "
                "or mor (5 %, 2.996/V)"
            )
        option_choice(convention, VISIBILITY_CONVENTIONS, "--visibility-convention")
        weather["visibility"] = option_quantity(visibility, "length", "--visibility")
        weather["convention"] = convention
        source = f"visibility {visibility} ({convention})"
    else:
        return {}
    gamma = atmosphere.extinction_for_band(band, **weather)
    term, visual_range = atmosphere.extinction_term(gamma)
    # Table 7.2's visual ranges describe the visible band's extinction: for another band the
    # same number of Np/km is other weather (fog:low is 0.4 Np/km in the LWIR, a visual range of
    # well under 1 km, not "6 - 30 km, clear to hazy"), so only its term is kept there.
    visible = band is not None and band_name_or_none(band) == "visible"
    name, _, level = weather.get("obscurant", "").partition(":")
    words = atmosphere.EXTINCTION_LEVEL_WORDS
    parts = [f"{words[level]} {name}, the {level} value of its Table 7.1 cell"] if name else []
    if visible:
        parts.append(f"{term} extinction, visual range {visual_range} (Table 7.2)")
    else:
        parts.append(
            f"{term} extinction on Table 7.2's scale (its visual ranges are the visible band's)"
        )
    description = "; ".join(parts)
    return {
        "extinction_np_per_m": gamma,
        "extinction_np_per_km": gamma * 1e3,
        "term": term,
        "visual_range": visual_range if visible else None,
        "description": description,
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
    sky_temperature: str | None = None,
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
            ("--sky-temperature", sky_temperature),
        ):
            if value is not None:
                raise ValueError(
                    f"{option} is used with --target-temperature and --background-temperature"
                )
    if scr is not None:
        return {"scr": _number(scr, "--scr", ">= 0")}
    if region is not None:
        return {"region": option_choice(region, CLUTTER_REGIONS, "--clutter")}
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
    t_sky = None
    if sky_temperature is not None:
        t_sky = _temperature(sky_temperature, "--sky-temperature")
    seen = scene_signature(
        band,
        t_t,
        t_b,
        target_emissivity=eps_t,
        background_emissivity=eps_b,
        clutter_std=sigma_t,
        sky_temperature=t_sky,
    )
    info: dict[str, Any] = {
        "target_temperature_k": t_t,
        "background_temperature_k": t_b,
        "contrast_w_per_m2": float(seen.contrast),
    }
    if t_sky is not None:  # the sky's reflection can turn the contrast negative (§6.3)
        info["sky_temperature_k"] = t_sky
        info["contrast_sign"] = int(seen.sign)
    if seen.scr is not None:
        info["clutter_w_per_m2"] = float(seen.clutter)
        info["scr"] = float(seen.scr)
    return info


@dataclass(frozen=True)
class RangeOptions:
    """The options of a range case as typed: the input of :func:`range_setup`.

    Every field is the text of one option of ``targetacq dri`` (``--focal-length`` is
    ``focal_length``), with its unit where it is a quantity (``"17um"``), or None where the option
    is not given; a few are numbers already (``pixels``, ``f_number``, ``scr``, ``emissivity``,
    ``background_emissivity``, ``nec``, ``contrast``). :func:`range_setup` checks them all. The
    help text of each option is :data:`targetacq.run.option_table.RANGE_CASE_OPTIONS`.

    Attributes
    ----------
    pitch, focal_length : str, optional
        Pixel pitch and focal length [length], e.g. ``"17um"``, ``"75mm"``.
    ifov, hfov : str, optional
        Pixel IFOV, or the horizontal field of view across ``pixels`` [angle], e.g.
        ``"0.227mrad"``, ``"12deg"``.
    pixels : int, optional
        Pixels across ``hfov``.
    projection, pixel_density : str, optional
        How ``hfov`` over ``pixels`` gives the IFOV
        (:data:`targetacq.physics.optics.FIELD_OF_VIEW_PROJECTIONS`), and how EN 62676-4 counts
        pixel density (:data:`PIXEL_DENSITY_DEFINITIONS`).
    aperture, wavelength : str, optional
        Aperture diameter and wavelength of the diffraction limit [length].
    f_number : float, optional
        Lens F-number, instead of ``aperture`` (aperture = focal length / F#) [1].
    blur : str, optional
        Angular standard deviation of a Gaussian optics blur [angle].
    critical_dimension : str, optional
        The target's critical dimension [length], e.g. ``"2.3m"``.
    target : str, optional
        A named target (:data:`targetacq.physics.targets.TARGETS`), instead of
        ``critical_dimension``.
    criterion, n50 : str, optional
        A criteria set by name, or user-defined N50s ``"D,R,I"`` [cycles].
    transform, bound : str, optional
        The transform and the c2nveo bound.
    scr : float, optional
        Signal-to-clutter ratio [1].
    clutter : str, optional
        Table 3.5 clutter region (low, medium, high).
    band : str, optional
        Sensor band, by name or as limits, e.g. ``"8-12um"``.
    target_temperature, background_temperature : str, optional
        [temperature], e.g. ``"305K"`` or ``"32degC"``.
    emissivity, background_emissivity : float, optional
        In [0, 1] [1].
    sky_temperature : str, optional
        Effective sky temperature [temperature], e.g. ``"240K"``: surfaces of emissivity below 1
        reflect ``1 − ε`` of the sky's band exitance (§6.3), which can make the contrast
        negative; default no reflection.
    clutter_std : str, optional
        The background's temperature spread [temperature difference], e.g. ``"2K"``.
    extinction : str, optional
        Path extinction [extinction], e.g. ``"0.4/km"`` or ``"1.7dB/km"``.
    obscurant, visibility, visibility_convention : str, optional
        A Table 7.1 obscurant ``name[:level]``, or a visibility [length] and its convention.
    atmosphere, aerosol, path_altitude : str, optional
        A named atmosphere (:mod:`targetacq.physics.named_atmospheres`): model atmosphere,
        aerosol and the horizontal path's height [length]; ``visibility`` is then the aerosol's.
    noise_model : str, optional
        :data:`targetacq.acquisition.path_noise.NOISE_MODELS` (default: ``variance-sum``, or none
        where an MRTD curve already holds the noise).
    snr_law : str, optional
        :data:`targetacq.acquisition.path_noise.SNR_LAWS` (default ``contrast``).
    netd, netd_temperature, delta_t : str, optional
        The NETD [temperature difference], the temperature it is quoted at [temperature], and
        the target's ΔT [temperature difference].
    nec, contrast : float, optional
        A TV camera's noise-equivalent contrast and the target's contrast [1].
    sky_to_ground : float, optional
        The TV camera's sky-to-ground ratio [1], >= 0: the path's airlight reduces the contrast
        by Duntley's law (:func:`targetacq.physics.atmosphere.contrast_transmittance`).
    hot_spot_ratio, hot_spot_size : float, str, optional
        A graded hot spot: its own SCR [1] and its linear size [length]
        (:func:`targetacq.acquisition.cues.hot_spot_weight`).
    target_speed : str, optional
        The target's speed across the line of sight [speed], e.g. ``"10m/s"``: a graded motion
        cue (:func:`targetacq.acquisition.cues.motion_weight`).
    target_area : str, optional
        Area of the target as seen [area].
    mrtd : str, optional
        Path of an MRTD curve CSV (frequency [cycles/mrad], mrtd [K]).
    resolution_model : str, optional
        :data:`targetacq.core.cases.RESOLUTION_MODELS` (default: mrtd with ``mrtd``, else
        johnson); see :mod:`targetacq.run.ttp_options`.
    jitter, smear, cn2, frame_rate, scene_contrast : str, optional
        The TTP metric's line-of-sight jitter [angle], motion smear [angle], Cn² [structure
        constant], frame rate [frequency] and scene contrast temperature [temperature
        difference].
    semantics : str, optional
        :data:`targetacq.acquisition.probabilities.ACQUISITION_SEMANTICS`.
    probability : str, optional
        One probability or several separated by commas, e.g. ``"0.5,0.8"``.
    example : bool
        Fill the sensor and target not given from the bundled example camera.

    Examples
    --------
    >>> RangeOptions.from_mapping({"pitch": "17um", "focal_length": "75mm"}).pitch
    '17um'
    >>> RangeOptions.from_mapping({"focal": "75mm"})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: unknown range-case option(s) 'focal'; valid options: pitch, focal_length, ...
    """

    pitch: str | None = None
    focal_length: str | None = None
    ifov: str | None = None
    hfov: str | None = None
    pixels: int | None = None
    projection: str | None = None
    pixel_density: str | None = None
    aperture: str | None = None
    f_number: float | None = None
    wavelength: str | None = None
    blur: str | None = None
    critical_dimension: str | None = None
    target: str | None = None
    criterion: str | None = None
    n50: str | None = None
    transform: str | None = None
    bound: str | None = None
    scr: float | None = None
    clutter: str | None = None
    band: str | None = None
    target_temperature: str | None = None
    background_temperature: str | None = None
    emissivity: float | None = None
    background_emissivity: float | None = None
    sky_temperature: str | None = None
    clutter_std: str | None = None
    extinction: str | None = None
    obscurant: str | None = None
    visibility: str | None = None
    visibility_convention: str | None = None
    atmosphere: str | None = None
    aerosol: str | None = None
    path_altitude: str | None = None
    noise_model: str | None = None
    snr_law: str | None = None
    netd: str | None = None
    netd_temperature: str | None = None
    delta_t: str | None = None
    nec: float | None = None
    contrast: float | None = None
    sky_to_ground: float | None = None
    hot_spot_ratio: float | None = None
    hot_spot_size: str | None = None
    target_speed: str | None = None
    target_area: str | None = None
    mrtd: str | None = None
    resolution_model: str | None = None
    jitter: str | None = None
    smear: str | None = None
    cn2: str | None = None
    frame_rate: str | None = None
    scene_contrast: str | None = None
    semantics: str | None = None
    probability: str | None = None
    example: bool = False

    @classmethod
    def from_mapping(cls, options: Mapping[str, Any]) -> RangeOptions:
        """The options of a mapping of option name to value (None: not given).

        Raises
        ------
        ValueError
            If a key is not an option, naming it and the valid options.
        """
        unknown = [key for key in options if key not in _OPTION_DEFAULTS]
        if unknown:
            raise ValueError(
                f"unknown range-case option(s) {', '.join(repr(k) for k in unknown)}; valid "
                f"options: {', '.join(_OPTION_DEFAULTS)}"
            )
        # The fields set at once, as the generated __init__ sets them (it has no checks): it
        # sets each of the 40 through object.__setattr__, a quarter of the time a sweep's
        # point takes to read.
        read = object.__new__(cls)
        read.__dict__.update(_OPTION_DEFAULTS)
        read.__dict__.update(options)
        return read


_OPTION_DEFAULTS = {f.name: f.default for f in fields(RangeOptions)}
"""The fields of :class:`RangeOptions` and their defaults, in order."""


@dataclass(frozen=True)
class RangeSetup:
    """Everything the dri, plot and report commands read from the sensor/target/path options:
    the range case, and for the output how the sensor, the path and the scene were given."""

    case: RangeCase
    sensor: dict[str, float]
    path: dict[str, Any]
    scene: dict[str, Any]
    probabilities: list[float]
    sized: bool = True
    """Whether the target's critical dimension enters (not for a pixel-density criterion)."""

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


@dataclass(frozen=True)
class RangeReading:
    """The options of a range case read (:func:`read_range_options`): every option checked on
    its own and turned into SI numbers and choices, before the optics kernels and the case's
    checks (:func:`range_case`), which run once on the arrays of many points stacked
    (:func:`stack_readings`).

    Attributes
    ----------
    numbers : mapping
        The point's numbers [SI] by name: ``critical_dimension``, the sensor's (``pitch``,
        ``focal_length``, ``ifov``, ``hfov``, ``pixels``, ``f_number``, as given) and the other
        array fields of :class:`targetacq.core.cases.RangeCase` given; floats, or arrays of one
        shape for stacked points.
    texts : mapping
        The option texts the kernels' errors name (``pitch``, ``focal_length``), stacked alike.
    settings : mapping
        Everything else the case is made of: how the resolution is given, the projection and
        pixel density, the criterion, transform and its options, clutter region, noise model,
        semantics and MRTD curve. Points with equal settings and the same numbers given stack.
    sensor, path, scene : dict
        The description of how the sensor (so far: the kernels add theirs), the path and the
        scene were given; empty for stacked points.
    probabilities : list of float
    sized : bool
        Whether the target's critical dimension enters (not for a pixel-density criterion).
    """

    numbers: Mapping[str, Any]
    texts: Mapping[str, Any]
    settings: Mapping[str, Any]
    sensor: dict[str, Any]
    path: dict[str, Any]
    scene: dict[str, Any]
    probabilities: list[float]
    sized: bool = True


_CASE_NUMBERS = (
    "wavelength",
    "aperture",
    "blur_sigma",
    "extinction",
    "scr",
    "contrast",
    "noise_equivalent_contrast",
    "target_area",
    "sky_to_ground",
    "hot_spot_ratio",
    "hot_spot_size",
    "target_speed",
)
"""The numbers of a reading that are :class:`targetacq.core.cases.RangeCase` fields as they
are (beside ``critical_dimension``; the IFOV comes from the sensor's numbers)."""


def range_setup(
    options: RangeOptions | Mapping[str, Any], default_probability: str = "0.5"
) -> RangeSetup:
    """The range case and its description from the options of `dri` (also `plot curves` and
    `report`, whose ``default_probability`` differs); every option checked finite and in its
    domain, and every option that would be ignored refused, naming it.

    :func:`read_range_options` then :func:`range_case`, for one point.

    Parameters
    ----------
    options : RangeOptions or mapping
        The options as typed (text with units), or a mapping of option name to value (None: not
        given), read by :meth:`RangeOptions.from_mapping` (an unknown name raises).
    default_probability : str
        The probabilities asked for when ``options.probability`` is not given, e.g. ``"0.5"``.

    Returns
    -------
    RangeSetup

    Examples
    --------
    >>> setup = range_setup(RangeOptions(ifov="0.2mrad", critical_dimension="2.3m"))
    >>> setup.case.transform, setup.probabilities
    ('ttpf', [0.5])
    """
    reading = read_range_options(options, default_probability)
    case, sensor = range_case(reading)
    return RangeSetup(
        case=case,
        sensor={**reading.sensor, **sensor},
        path=reading.path,
        scene=reading.scene,
        probabilities=reading.probabilities,
        sized=reading.sized,
    )


def stack_readings(readings: Sequence[RangeReading], shape: tuple[int, ...]) -> RangeReading:
    """Readings of equal settings and the same numbers given as one reading of arrays of
    ``shape`` (one element per reading, in order), for :func:`range_case` to make one case of
    them all; the descriptions (sensor, path, scene) are each point's own, not stacked.

    Examples
    --------
    >>> readings = [read_range_options(RangeOptions(ifov=f"{i}mrad", critical_dimension="2m"),
    ...     "0.5") for i in (0.1, 0.2)]
    >>> range_case(stack_readings(readings, (2,)))[0].ifov.tolist()
    [0.0001, 0.0002]
    """
    first = readings[0]
    return dataclasses.replace(
        first,
        numbers={
            name: np.asarray([r.numbers[name] for r in readings], dtype=float).reshape(shape)
            for name in first.numbers
        },
        texts={
            name: np.asarray([r.texts[name] for r in readings], dtype=object).reshape(shape)
            for name in first.texts
        },
        sensor={},
        path={},
        scene={},
    )


def range_case(reading: RangeReading) -> tuple[RangeCase, dict[str, Any]]:
    """The range case of read options, and the sensor's description the optics kernels add
    (its field of view, pixel density, F-number): the IFOV from
    :func:`targetacq.physics.optics.ifov` (or from the field of view), then the case's checks, once
    on the arrays of a stacked reading (:func:`stack_readings`).

    Raises
    ------
    ValueError
        For an IFOV outside (0, π) (naming the options of the first point that gives one), or
        ``--noise-model`` where no noise acts.

    Examples
    --------
    >>> case, sensor = range_case(read_range_options(
    ...     RangeOptions(pitch="17um", focal_length="75mm", critical_dimension="2.3m"), "0.5"))
    >>> round(case.ifov * 1e3, 4), sensor
    (0.2267, {})
    """
    numbers, settings = reading.numbers, reading.settings
    ifov_rad, sensor = _sensor_resolution(reading)
    case = RangeCase(
        numbers["critical_dimension"],
        ifov_rad,
        **{name: numbers[name] for name in _CASE_NUMBERS if name in numbers},
        semantics=settings["semantics"],
        criterion=settings["criterion"],
        transform=settings["transform"],
        options=settings["options"],
        region=settings["region"],
        mrtd=settings["mrtd"],
        ttp=ttp_system(numbers, ifov_rad) if settings["resolution_model"] == "ttp" else None,
        path=settings.get("path"),
        noise_model=settings["noise_model"],
        snr_law=settings["snr_law"] or "contrast",
    )
    if settings["snr_law"] is not None and case.noise_equivalent_contrast is None:
        raise ValueError("--snr-law applies to a sensor's noise: give --netd or --nec")
    if settings["noise_model"] is not None and not case.noisy:
        raise ValueError(
            "--noise-model applies to a noisy path or sensor: give --extinction, --obscurant, "
            "--visibility, --netd or --nec"
        )
    return case, sensor


def read_range_options(
    options: RangeOptions | Mapping[str, Any], default_probability: str
) -> RangeReading:
    """The options of a range case read into SI numbers and choices, each checked on its own
    (finite, in its domain, no option ignored), naming the option: all of
    :func:`range_setup` but the optics kernels and the case's checks (:func:`range_case`).

    Examples
    --------
    >>> reading = read_range_options(RangeOptions(pitch="17um", focal_length="75mm",
    ...     critical_dimension="2.3m"), "0.5")
    >>> reading.numbers
    {'pitch': 1.7e-05, 'focal_length': 0.075, 'critical_dimension': 2.3}
    """
    o = options if isinstance(options, RangeOptions) else RangeOptions.from_mapping(options)
    pitch, focal_length, aperture = o.pitch, o.focal_length, o.aperture
    wavelength, critical_dimension = o.wavelength, o.critical_dimension
    if o.transform is not None:
        option_choice(o.transform, TRANSFORMS, "--transform")
    if o.target is not None:
        if critical_dimension is not None:
            raise ValueError("give --target or --critical-dimension, not both")
        # a named target sets the critical dimension (and replaces --example's own target)
        named = TARGETS[option_choice(o.target, TARGETS, "--target")]
        critical_dimension = f"{named.critical_dimension!r}m"
    if o.example:
        camera = example_camera()
        if o.ifov is None and o.hfov is None and o.pixels is None:
            pitch = pitch or camera["pitch"]
            focal_length = focal_length or camera["focal_length"]
        if o.blur is None:
            aperture = aperture or camera["aperture"]
            wavelength = wavelength or camera["wavelength"]
        critical_dimension = critical_dimension or camera["critical_dimension"]
    sized = not _pixel_density(o.criterion, o.n50)
    if critical_dimension is None:
        if sized:
            raise ValueError(
                "--critical-dimension is required (e.g. 2.3m), or --target NAME, or use --example"
            )
        # A pixel-density criterion counts pixels per metre of the scene, whatever the
        # target's size: a placeholder the case needs and no output reports.
        critical_dimension = "1m"
    d = option_quantity(critical_dimension, "length", "--critical-dimension")
    way, numbers, sensor = _sensor_reading(
        pitch, focal_length, o.ifov, o.hfov, o.pixels, o.projection
    )
    numbers["critical_dimension"] = d
    optics_kw: dict[str, Any] = {}
    if o.f_number is not None:
        if aperture is not None:
            raise ValueError("give --aperture or --f-number, not both")
        if "focal_length_m" not in sensor:
            raise ValueError("--f-number needs --focal-length (aperture = focal length / F#)")
        numbers["f_number"] = _number(o.f_number, "--f-number", "> 0")
        if wavelength is None:
            raise ValueError("--f-number gives the aperture for diffraction: give --wavelength")
    if (aperture is None and o.f_number is None) != (wavelength is None):
        raise ValueError("--aperture and --wavelength go together (diffraction limit)")
    if wavelength is not None:
        optics_kw["aperture"] = (
            sensor["focal_length_m"] / o.f_number
            if o.f_number is not None
            else option_quantity(str(aperture), "length", "--aperture")
        )
        optics_kw["wavelength"] = option_quantity(wavelength, "length", "--wavelength")
    if o.blur is not None:
        optics_kw["blur_sigma"] = parse_quantity(o.blur, "angle", "--blur")
        if not 0 <= optics_kw["blur_sigma"] < math.pi:
            raise ValueError(f"--blur must be in [0, 180) deg; got {o.blur!r}")
    if o.n50 is not None and o.criterion is not None:
        raise ValueError("give either --criterion or --n50, not both")
    crit = (
        option_criterion(o.n50)
        if o.n50 is not None
        else get_criterion(
            option_choice(
                "johnson" if o.criterion is None else o.criterion, CRITERIA, "--criterion"
            )
        )
    )
    if not crit.gives_probabilities:
        # A pixel-density criterion gives thresholds, one range each: no probability, no
        # transform, no semantics, and pixel density counted its own way (--pixel-density).
        for option, value in (
            ("--probability", o.probability),
            ("--transform", o.transform),
            ("--semantics", o.semantics),
            ("--projection", o.projection),
        ):
            if value is not None:
                raise ValueError(
                    f"--criterion {crit.name} gives pixel-density thresholds; {option} does "
                    "not apply"
                )
    transform_options: dict[str, Any] = {}
    if o.bound is not None:
        transform_options["bound"] = option_choice(o.bound, C2NVEO_BOUNDS, "--bound")
    band_limits_m = option_band(o.band) if o.band is not None else None
    named_path = _named_path(o, band_limits_m)
    path = (
        option_path(o.extinction, o.obscurant, o.visibility, o.visibility_convention, band_limits_m)
        if named_path is None
        else named_path_description(named_path.path, named_path.band)
    )
    scene = _clutter(
        o.scr,
        o.clutter,
        o.clutter_std,
        o.target_temperature,
        o.background_temperature,
        o.emissivity,
        o.background_emissivity,
        band_limits_m,
        o.sky_temperature,
    )
    if o.noise_model is not None:
        option_choice(o.noise_model, NOISE_MODELS, "--noise-model")
    if o.snr_law is not None:
        option_choice(o.snr_law, SNR_LAWS, "--snr-law")
    if o.semantics is not None:
        option_choice(o.semantics, ACQUISITION_SEMANTICS, "--semantics")
    if o.pixel_density is not None:
        option_choice(o.pixel_density, PIXEL_DENSITY_DEFINITIONS, "--pixel-density")
    density = None
    if not crit.gives_probabilities and "pixels" in numbers:  # a field of view is given
        density = o.pixel_density or "plane"  # EN 62676-4's pixel density (_sensor_resolution)
    elif o.pixel_density is not None:
        raise ValueError("--pixel-density applies to a pixel-density criterion with --hfov")
    noise_kw = _sensor_noise(
        o.netd, o.netd_temperature, o.delta_t, o.nec, o.contrast, o.mrtd, scene, band_limits_m
    )
    if (
        scene.get("contrast_w_per_m2") == 0.0
        and "noise_equivalent_contrast" not in noise_kw
        and "scr" not in scene
        and "region" not in scene
    ):
        warnings.warn(
            "the target has no contrast against its background, but without the sensor's noise "
            "(--netd or --nec) or clutter the contrast does not enter the model: the ranges are "
            "the geometric ones (cycles on target only); give --netd or --nec for the contrast "
            "to count",
            UserWarning,
            stacklevel=3,
        )
    if o.sky_to_ground is not None:
        if o.nec is None:
            raise ValueError(
                "--sky-to-ground is a TV camera's: it reduces the contrast against --nec"
            )
        noise_kw["sky_to_ground"] = _number(o.sky_to_ground, "--sky-to-ground", ">= 0")
    if o.hot_spot_ratio is not None:
        numbers["hot_spot_ratio"] = _number(o.hot_spot_ratio, "--hot-spot-ratio", ">= 0")
    if o.hot_spot_size is not None:
        if o.hot_spot_ratio is None:
            raise ValueError("--hot-spot-size grades a hot spot: give --hot-spot-ratio too")
        numbers["hot_spot_size"] = option_quantity(
            o.hot_spot_size, "length", "--hot-spot-size", zero_allowed=True
        )
    if o.target_speed is not None:
        numbers["target_speed"] = option_quantity(
            o.target_speed, "speed", "--target-speed", zero_allowed=True
        )
    if o.target_area is not None:
        if "noise_equivalent_contrast" not in noise_kw:
            raise ValueError("--target-area is used with the sensor's noise (--netd or --nec)")
        noise_kw["target_area"] = option_quantity(o.target_area, "area", "--target-area")
    model, ttp = read_resolution_model(
        {name: getattr(o, name) for name in ("resolution_model", *TTP_OPTIONS)}, optics_kw, noise_kw
    )
    if model == "ttp":  # the NETD goes into the TTP metric's noise, not a separate SNR
        if o.criterion is None and o.n50 is None:  # V50s go with V, not Johnson's N50s
            crit = get_criterion("ttp-vehicles")
        numbers["ttp_netd"] = noise_kw.pop("noise_equivalent_contrast")
        numbers |= {f"ttp_{name}": value for name, value in ttp.items()}
    # a zero extinction (--extinction 0/km) is a clear path: no noise from it
    extinction = path.get("extinction_np_per_m") or None
    numbers |= optics_kw | {name: value for name, value in noise_kw.items() if name != "mrtd"}
    if extinction is not None:
        numbers["extinction"] = extinction
    if scene.get("scr") is not None:
        numbers["scr"] = scene["scr"]
    return RangeReading(
        numbers=numbers,
        texts={"pitch": pitch, "focal_length": focal_length} if way == "lens" else {},
        settings={
            "resolution": way,
            "projection": (o.projection or "angular") if way == "fov" else None,
            "pixel_density": density,
            "semantics": o.semantics or "nested",
            "criterion": crit,
            "transform": o.transform or ("ttp" if model == "ttp" else "ttpf"),
            "options": transform_options,
            "region": scene.get("region"),
            "mrtd": noise_kw.get("mrtd"),
            "noise_model": o.noise_model,
            "resolution_model": model,
            "path": named_path,
            "snr_law": o.snr_law,
        },
        sensor=sensor,
        path=path,
        scene=scene,
        probabilities=option_probabilities(
            default_probability if o.probability is None else o.probability
        ),
        sized=sized,
    )


def _named_path(o: RangeOptions, band: tuple[float, float] | None) -> NamedBandPath | None:
    """The named atmosphere of --atmosphere, --aerosol, --visibility and --path-altitude in the
    sensor's band, or None where neither --atmosphere nor --aerosol is given."""
    named = option_named_path(o.atmosphere, o.aerosol, o.visibility, o.path_altitude)
    if named is None:
        return None
    given = [
        flag
        for flag, value in (
            ("--extinction", o.extinction),
            ("--obscurant", o.obscurant),
            ("--visibility-convention", o.visibility_convention),
        )
        if value is not None
    ]
    if given:
        raise ValueError(
            f"{' and '.join(given)} do not go with a named atmosphere (--atmosphere, --aerosol): "
            "its --visibility is the aerosol's meteorological range"
        )
    if band is None:
        raise ValueError("a named atmosphere needs --band: " + ", ".join(NAMED_BANDS))
    return NamedBandPath(named, band)


def _pixel_density(criterion: str | None, n50: str | None) -> bool:
    """Whether the options name a pixel-density criterion (EN 62676-4's levels), which needs no
    critical dimension."""
    named = CRITERIA.get(criterion) if n50 is None and criterion is not None else None
    return named is not None and not named.gives_probabilities


def dri_report(setup: RangeSetup) -> dict[str, Any]:
    case, crit = setup.case, setup.criterion
    rows = []
    # Every probability in one solve (the bisection runs over them together).
    found = ranges.case_ranges(case, np.asarray(setup.probabilities, dtype=float))
    for k, p in enumerate(setup.probabilities):
        for task, r in found.items():
            value = float(np.broadcast_to(r, (len(setup.probabilities),))[k])
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
            # A pixel-density criterion does not use it (pixels per metre of the scene).
            "critical_dimension_m": case.critical_dimension if setup.sized else None,
            **setup.scene,
            **_noise_report(case),
        },
        "path": setup.path,
        "criterion": crit.name,
        "criterion_kind": crit.kind,
        "transform": case.transform if crit.gives_probabilities else None,
        "options": case.options,
        "noise_model": case.applied_noise_model if case.noisy else None,
        "snr_law": case.snr_law if case.applies_snr and case.noise_equivalent_contrast else None,
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
    if case.sky_to_ground is not None:
        out["sky_to_ground"] = float(case.sky_to_ground)
    if case.mrtd is not None:
        out["mrtd_cutoff_cycles_per_mrad"] = case.mrtd.cutoff * 1e-3
    if case.ttp is not None:
        out["ttp"] = {
            "netd_k": float(case.ttp.netd),
            "frame_rate_hz": float(case.ttp.frame_rate),
            "jitter_rad": float(case.ttp.jitter),
            "smear_rad": float(case.ttp.smear),
            "cn2_m_minus_2_3": float(case.ttp.cn2),
            "scene_contrast_k": float(case.ttp.scene_contrast),
        }
    return out
