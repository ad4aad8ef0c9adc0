"""The options of a range case, defined once for every front end, and lists of them.

:data:`RANGE_CASE_OPTIONS` names every field of
:class:`targetacq.run.range_options.RangeOptions` (the input of
:func:`~targetacq.run.range_options.range_setup`) with its type, help text and group: the CLI
builds its options from it (:mod:`targetacq.cli.options`), and a web form can too.

Any option may take a list of values separated by commas (``focal_length="35mm,50mm,75mm"``);
:func:`option_lists` finds them and :func:`option_product` gives one set of options per
combination, in a fixed order (the first option varies slowest). Two options keep their commas:
``probability`` (already a list: the probabilities asked for) and ``n50`` (three numbers D,R,I;
several sets are separated by ``;``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, fields
from typing import Any

from targetacq.acquisition.criteria import CRITERIA
from targetacq.acquisition.path_noise import NOISE_MODELS, SNR_LAWS
from targetacq.acquisition.probabilities import ACQUISITION_SEMANTICS
from targetacq.acquisition.transforms import C2NVEO_BOUNDS, CLUTTER_REGIONS, TRANSFORMS
from targetacq.core.cases import RESOLUTION_MODELS
from targetacq.physics.atmosphere import EXTINCTION_LEVEL_WORDS, OBSCURANTS, VISIBILITY_CONVENTIONS
from targetacq.physics.bands import BANDS
from targetacq.physics.named_atmospheres import AEROSOLS, ATMOSPHERES
from targetacq.physics.optics import FIELD_OF_VIEW_PROJECTIONS
from targetacq.physics.targets import TARGETS
from targetacq.run.range_options import PIXEL_DENSITY_DEFINITIONS, RangeOptions
from targetacq.run.uncertainty import MAX_SAMPLES, MIN_SAMPLES, TABLE_N50_SPREAD

__all__ = [
    "LIST_SEPARATORS",
    "RANGE_CASE_OPTIONS",
    "UNCERTAINTY_OPTIONS",
    "OptionSpec",
    "option_coverage",
    "option_lists",
    "option_product",
    "split_list",
    "typed_options",
]


SENSOR, TARGET, SCENE, PATH, NOISE, MODEL = (
    "Sensor",
    "Target",
    "Scene and clutter",
    "Path (atmosphere)",
    "Sensor noise and resolution model",
    "Model",
)
"""The ``--help`` panels of the range-case options."""


@dataclass(frozen=True)
class OptionSpec:
    """One range-case option: its keyword name, Python type, help text and ``--help`` panel;
    the kind of quantity or the registry of names it takes, if any."""

    name: str
    kind: type
    help: str
    panel: str
    quantity: str | None = None
    """The kind of quantity of each value (a key of :data:`targetacq.base.units.DIMENSIONS`), if
    any."""
    choices: Any = None
    """The registry whose names the option takes (its keys are the choices), if any."""

    @property
    def flag(self) -> str:
        return "--" + self.name.replace("_", "-")


def _names(registry: Any) -> str:
    return ", ".join(registry)


RANGE_CASE_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec("pitch", str, "Pixel pitch, e.g. 17um.", SENSOR, quantity="length"),
    OptionSpec("focal_length", str, "Focal length, e.g. 75mm.", SENSOR, quantity="length"),
    OptionSpec("ifov", str, "Pixel IFOV, e.g. 0.227mrad.", SENSOR, quantity="angle"),
    OptionSpec("hfov", str, "Horizontal field of view, e.g. 12deg.", SENSOR, quantity="angle"),
    OptionSpec("pixels", int, "Pixels across --hfov, e.g. 640.", SENSOR),
    OptionSpec(
        "projection",
        str,
        "How --hfov over --pixels gives the IFOV: "
        f"{_names(FIELD_OF_VIEW_PROJECTIONS)} (default angular: HFOV / pixels, datasheets; "
        "rectilinear: 2 tan(HFOV/2) / pixels).",
        SENSOR,
        choices=FIELD_OF_VIEW_PROJECTIONS,
    ),
    OptionSpec(
        "pixel_density",
        str,
        f"EN 62676-4 pixel density from --hfov: {_names(PIXEL_DENSITY_DEFINITIONS)} (default "
        "plane: scene width 2R tan(HFOV/2); arc: R · HFOV).",
        SENSOR,
        choices=PIXEL_DENSITY_DEFINITIONS,
    ),
    OptionSpec(
        "aperture",
        str,
        "Lens aperture diameter for diffraction, e.g. 75mm.",
        SENSOR,
        quantity="length",
    ),
    OptionSpec("f_number", float, "Lens F-number: aperture = focal length / F#.", SENSOR),
    OptionSpec(
        "wavelength", str, "Wavelength for diffraction, e.g. 10um.", SENSOR, quantity="length"
    ),
    OptionSpec(
        "blur",
        str,
        "Angular std. dev. of a Gaussian optics blur, e.g. 0.05mrad.",
        SENSOR,
        quantity="angle",
    ),
    OptionSpec(
        "critical_dimension",
        str,
        "Target critical dimension, e.g. 2.3m.",
        TARGET,
        quantity="length",
    ),
    OptionSpec(
        "target",
        str,
        f"Named target: {_names(TARGETS)} (sets the critical dimension).",
        TARGET,
        choices=TARGETS,
    ),
    OptionSpec(
        "criterion",
        str,
        f"Criteria set: {_names(CRITERIA)} (default johnson).",
        MODEL,
        choices=CRITERIA,
    ),
    OptionSpec(
        "n50", str, "User-defined N50 cycles for detection,recognition,identification.", MODEL
    ),
    OptionSpec(
        "transform",
        str,
        f"Transform: {_names(TRANSFORMS)} (default ttpf).",
        MODEL,
        choices=TRANSFORMS,
    ),
    OptionSpec(
        "bound", str, f"c2nveo bound: {_names(C2NVEO_BOUNDS)}.", MODEL, choices=C2NVEO_BOUNDS
    ),
    OptionSpec("scr", float, "Signal-to-clutter ratio (schmieder-weathersby).", SCENE),
    OptionSpec(
        "clutter",
        str,
        f"Clutter region (schmieder-weathersby): {_names(CLUTTER_REGIONS)}.",
        SCENE,
        choices=CLUTTER_REGIONS,
    ),
    OptionSpec("band", str, f"Sensor band: {_names(BANDS)} or e.g. 8-12um.", SENSOR, choices=BANDS),
    OptionSpec(
        "target_temperature",
        str,
        "Target temperature, e.g. 305K or 32degC.",
        SCENE,
        quantity="temperature",
    ),
    OptionSpec(
        "background_temperature",
        str,
        "Background temperature, e.g. 295K.",
        SCENE,
        quantity="temperature",
    ),
    OptionSpec("emissivity", float, "Target emissivity in [0, 1] (default 1).", SCENE),
    OptionSpec(
        "background_emissivity", float, "Background emissivity in [0, 1] (default 1).", SCENE
    ),
    OptionSpec(
        "sky_temperature",
        str,
        "Effective sky temperature, e.g. 240K: surfaces of emissivity < 1 reflect the sky "
        "(default: no reflection).",
        SCENE,
        quantity="temperature",
    ),
    OptionSpec(
        "clutter_std",
        str,
        "Background temperature spread (clutter), e.g. 2K; gives the SCR.",
        SCENE,
        quantity="temperature difference",
    ),
    OptionSpec(
        "hot_spot_ratio",
        float,
        "A hot spot's own signal-to-clutter ratio, e.g. 10: detection blends in the "
        "low-clutter curve by a weight (0.05 at 1, 0.95 at 10).",
        SCENE,
    ),
    OptionSpec(
        "hot_spot_size",
        str,
        "The hot spot's size, e.g. 0.3m: below a pixel its contrast is diluted.",
        SCENE,
        quantity="length",
    ),
    OptionSpec(
        "target_speed",
        str,
        "Target speed across the line of sight, e.g. 10m/s: detection blends in the motion "
        "rule by a weight (0.5 at 1 pixel/s).",
        SCENE,
        quantity="speed",
    ),
    OptionSpec(
        "extinction",
        str,
        "Path extinction, e.g. 0.4/km (Np/km) or 1.7dB/km.",
        PATH,
        quantity="extinction",
    ),
    OptionSpec(
        "obscurant",
        str,
        f"Table 7.1 obscurant[:low|nominal|high]: {_names(OBSCURANTS)}; the level is where in "
        "the band's cell: "
        + ", ".join(f"{k} = {v}" for k, v in EXTINCTION_LEVEL_WORDS.items())
        + " (fog:low is light fog).",
        PATH,
        choices=OBSCURANTS,
    ),
    OptionSpec(
        "visibility",
        str,
        "Visibility, e.g. 7.5km: the visible band's extinction, or with --atmosphere/--aerosol "
        "the aerosol's meteorological range (any band).",
        PATH,
        quantity="length",
    ),
    OptionSpec(
        "visibility_convention",
        str,
        f"Visibility convention: {_names(VISIBILITY_CONVENTIONS)}.",
        PATH,
        choices=VISIBILITY_CONVENTIONS,
    ),
    OptionSpec(
        "atmosphere",
        str,
        f"Named model atmosphere (LOWTRAN7 table, water vapour): {_names(ATMOSPHERES)}.",
        PATH,
        choices=ATMOSPHERES,
    ),
    OptionSpec(
        "aerosol",
        str,
        f"Aerosol of the named atmosphere: {_names(AEROSOLS)} (default rural).",
        PATH,
        choices=AEROSOLS,
    ),
    OptionSpec(
        "path_altitude",
        str,
        "Height of the named atmosphere's horizontal path above sea level, e.g. 500m.",
        PATH,
        quantity="length",
    ),
    OptionSpec(
        "noise_model",
        str,
        f"Noise model: {_names(NOISE_MODELS)} (default variance-sum; none with --mrtd, whose "
        "curve already holds the noise and the path).",
        NOISE,
        choices=NOISE_MODELS,
    ),
    OptionSpec(
        "snr_law",
        str,
        f"SNR law with --netd or --nec: {_names(SNR_LAWS)} (default contrast: the apparent "
        "contrast against sensor and path-radiance noise, with a detection threshold; sonesson: "
        "the thesis's contrast-free Eq. (7.7)).",
        NOISE,
        choices=SNR_LAWS,
    ),
    OptionSpec(
        "netd",
        str,
        "Thermal camera's NETD, e.g. 50mK (needs --delta-t).",
        NOISE,
        quantity="temperature difference",
    ),
    OptionSpec(
        "netd_temperature",
        str,
        "Temperature at which the NETD is quoted, to turn the target and background "
        "temperatures into a ΔT (default 300K).",
        NOISE,
        quantity="temperature",
    ),
    OptionSpec(
        "delta_t",
        str,
        "Target-background temperature difference, e.g. 2K.",
        NOISE,
        quantity="temperature difference",
    ),
    OptionSpec("nec", float, "TV camera's noise-equivalent contrast, e.g. 0.01.", NOISE),
    OptionSpec("contrast", float, "Target contrast for --nec, e.g. 0.3.", NOISE),
    OptionSpec(
        "sky_to_ground",
        float,
        "TV sky-to-ground ratio (horizon over background radiance) for --nec: the path's "
        "airlight reduces the contrast, C·τ/(τ + (1 − τ)·K) (default: C·τ, K = 1).",
        NOISE,
    ),
    OptionSpec(
        "target_area",
        str,
        "Area of the target as seen, for its pixels (default: dimension²).",
        NOISE,
        quantity="area",
    ),
    OptionSpec(
        "mrtd",
        str,
        "MRTD curve CSV (frequency [cycles/mrad], mrtd [K]); needs --delta-t.",
        NOISE,
    ),
    OptionSpec(
        "resolution_model",
        str,
        f"Resolution model: {_names(RESOLUTION_MODELS)} (default mrtd with --mrtd, else "
        "johnson); ttp needs --aperture or --f-number, --wavelength, --netd and --delta-t.",
        NOISE,
        choices=RESOLUTION_MODELS,
    ),
    OptionSpec(
        "jitter",
        str,
        "Line-of-sight jitter, RMS per axis, e.g. 0.02mrad (ttp).",
        NOISE,
        quantity="angle",
    ),
    OptionSpec(
        "smear", str, "Image motion during one frame, e.g. 0.1mrad (ttp).", NOISE, quantity="angle"
    ),
    OptionSpec(
        "cn2",
        str,
        "Turbulence structure constant Cn², e.g. 1e-14m^(-2/3) (ttp).",
        NOISE,
        quantity="structure constant",
    ),
    OptionSpec(
        "frame_rate", str, "Frame rate, e.g. 30Hz (ttp; default 30Hz).", NOISE, quantity="frequency"
    ),
    OptionSpec(
        "scene_contrast",
        str,
        "Scene contrast temperature that sets the display gain, e.g. 5K (ttp; default 5K).",
        NOISE,
        quantity="temperature difference",
    ),
    OptionSpec(
        "semantics",
        str,
        f"Acquisition semantics: {_names(ACQUISITION_SEMANTICS)} (default nested).",
        MODEL,
        choices=ACQUISITION_SEMANTICS,
    ),
    OptionSpec(
        "probability",
        str,
        "Probability, or several separated by commas, e.g. 0.5,0.8.",
        MODEL,
    ),
)
"""Every field of :class:`~targetacq.run.range_options.RangeOptions` but ``example`` (a flag,
added by :func:`targetacq.cli.options.range_case_options`)."""

UNCERTAINTY = "Uncertainty (Monte Carlo)"
"""The ``--help`` panel of :data:`UNCERTAINTY_OPTIONS`."""

UNCERTAINTY_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec(
        "uncertainty",
        str,
        f"Monte Carlo samples for 5–95 % bands on the ranges and curves, e.g. 500 "
        f"({MIN_SAMPLES} to {MAX_SAMPLES}; default: no bands).",
        UNCERTAINTY,
    ),
    OptionSpec(
        "seed", str, "Seed of the Monte Carlo's draws, an integer (default 0).", UNCERTAINTY
    ),
    OptionSpec(
        "n50_spread",
        str,
        f"Relative spread of the N50s, e.g. 25% (default {TABLE_N50_SPREAD:.0%}: Sonesson "
        "Table 3.2's ±25 %).",
        UNCERTAINTY,
    ),
    OptionSpec(
        "observer_spread",
        str,
        "An observer's own relative spread of the N50s, e.g. 15% (default 0%).",
        UNCERTAINTY,
    ),
    OptionSpec(
        "netd_spread",
        str,
        "Relative spread of the NETD (--netd) or NEC (--nec), e.g. 10% (default 0%).",
        UNCERTAINTY,
    ),
    OptionSpec(
        "extinction_spread",
        str,
        "Relative spread of the path's extinction, e.g. 20% (default 0%).",
        UNCERTAINTY,
    ),
)
"""The Monte Carlo's options (:func:`targetacq.run.uncertainty.read_uncertainty`): every
spread a relative standard deviation, as a percentage, of a lognormal with its median at the
nominal value."""

_NOT_OPTIONS = {"example"}

LIST_SEPARATORS = {"n50": ";", "probability": None}
"""How an option separates a list of values: ``,`` unless named here (None: never a list)."""

_SPECS = {spec.name: spec for spec in RANGE_CASE_OPTIONS}


def option_coverage() -> tuple[set[str], set[str]]:
    """The fields of ``RangeOptions`` that have no option here, and the options here that
    ``RangeOptions`` does not have (both empty: a test keeps them so)."""
    wanted = {f.name for f in fields(RangeOptions)} - _NOT_OPTIONS
    have = set(_SPECS)
    return wanted - have, have - wanted


def _typed(name: str, text: str) -> Any:
    """One value of option ``name`` as its type (text stays text; numbers are parsed)."""
    kind = _SPECS[name].kind
    if kind is str:
        return text
    try:
        value = kind(text)
    except ValueError:
        what = "a whole number" if kind is int else "a number"
        raise ValueError(f"{_SPECS[name].flag} must be {what}; got {text!r}") from None
    if kind is float and math.isnan(value):
        raise ValueError(f"{_SPECS[name].flag} must be a number, not NaN; got {text!r}")
    return value


def option_lists(case_options: dict[str, Any]) -> dict[str, list[Any]]:
    """The options given with several values, in the order given: name → values.

    Parameters
    ----------
    case_options : dict
        Option name → value as typed (text), or None where not given.

    Returns
    -------
    dict
        Each option with two or more values → its values (typed: numbers parsed); options with
        one value or none are left out.

    Raises
    ------
    ValueError
        If a list has an empty item or the same value twice, naming the option.

    Examples
    --------
    >>> option_lists({"focal_length": "35mm,50mm", "pitch": "12um", "n50": "1,4,6.4;1,3,6"})
    {'focal_length': ['35mm', '50mm'], 'n50': ['1,4,6.4', '1,3,6']}
    """
    lists: dict[str, list[Any]] = {}
    for name, value in case_options.items():
        if name not in _SPECS or not isinstance(value, str):
            continue
        separator = LIST_SEPARATORS.get(name, ",")
        if separator is None or separator not in value:
            continue
        parts = split_list(_SPECS[name].flag, value, separator)
        lists[name] = [_typed(name, part) for part in parts]
    return lists


def split_list(flag: str, text: str, separator: str = ",") -> list[str]:
    """The items of a list given as text, stripped of spaces.

    Raises
    ------
    ValueError
        If an item is empty or a value appears twice, naming ``flag``.

    Examples
    --------
    >>> split_list("--probability", "0.5, 0.9")
    ['0.5', '0.9']
    """
    parts = [part.strip() for part in text.split(separator)]
    if any(part == "" for part in parts):
        raise ValueError(f"{flag}: empty item in the list {text!r}")
    if len(set(parts)) != len(parts):
        raise ValueError(f"{flag}: a value appears twice in the list {text!r}")
    return parts


def option_product(case_options: dict[str, Any]) -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """One set of options per combination of the listed values.

    Returns
    -------
    list of (dict, dict)
        For each combination (the first listed option varying slowest): the swept options'
        values, and the complete options for ``range_setup`` (numbers parsed).

    Examples
    --------
    >>> cases = option_product({"focal_length": "35mm,50mm", "pixels": None, "scr": "2,3"})
    >>> [swept for swept, _ in cases]  # doctest: +NORMALIZE_WHITESPACE
    [{'focal_length': '35mm', 'scr': 2.0}, {'focal_length': '35mm', 'scr': 3.0},
     {'focal_length': '50mm', 'scr': 2.0}, {'focal_length': '50mm', 'scr': 3.0}]
    """
    lists = option_lists(case_options)
    single = {
        name: _typed(name, value) if name in _SPECS and isinstance(value, str) else value
        for name, value in case_options.items()
        if name not in lists
    }
    names = list(lists)
    out = []
    for values in itertools.product(*(lists[name] for name in names)):
        swept = dict(zip(names, values, strict=True))
        out.append((swept, {**single, **swept}))
    return out


def typed_options(case_options: dict[str, Any], command: str) -> dict[str, Any]:
    """The options of a command that takes one value per option, numbers parsed.

    Raises
    ------
    ValueError
        If an option is given a list, naming it and ``command``.

    Examples
    --------
    >>> typed_options({"pixels": "640", "hfov": "12deg"}, "plot")
    {'pixels': 640, 'hfov': '12deg'}
    """
    lists = option_lists(case_options)
    if lists:
        flags = ", ".join(_SPECS[name].flag for name in lists)
        raise ValueError(
            f"{command} takes one value per option; {flags} got a list (targetacq sweep takes "
            "lists)"
        )
    ((_, options),) = option_product(case_options)
    return options
