"""Option groups shared by commands, defined once.

The sensor, target, scene, path, noise and model options of ``targetacq dri`` are the keyword
arguments of :func:`targetacq.services.range_case.range_setup`. :func:`range_case_options` adds
all of them to a command (``dri``, ``plot``, ``report``, ``sweep``, ``design``), grouped in
``--help`` by panel, so every command that takes them lists them and parses them itself: no
command re-parses another's arguments. The command receives them as one keyword argument,
``case_options`` (name → the text given, or None).
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, TypeVar

import typer

from targetacq.acquisition import ACQUISITION_SEMANTICS
from targetacq.atmosphere import OBSCURANTS, VISIBILITY_CONVENTIONS
from targetacq.bands import BANDS
from targetacq.criteria import CRITERIA
from targetacq.noise import NOISE_MODELS
from targetacq.optics import FIELD_OF_VIEW_PROJECTIONS
from targetacq.services.range_case import PIXEL_DENSITY_DEFINITIONS, range_setup
from targetacq.transforms import C2NVEO_BOUNDS, CLUTTER_REGIONS, TRANSFORMS

__all__ = ["RANGE_CASE_OPTIONS", "OptionSpec", "range_case_options"]

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
    """One range-case option: its keyword name, Python type, help text and ``--help`` panel."""

    name: str
    kind: type
    help: str
    panel: str

    @property
    def flag(self) -> str:
        return "--" + self.name.replace("_", "-")


def _names(registry: Any) -> str:
    return ", ".join(registry)


RANGE_CASE_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec("pitch", str, "Pixel pitch, e.g. 17um.", SENSOR),
    OptionSpec("focal_length", str, "Focal length, e.g. 75mm.", SENSOR),
    OptionSpec("ifov", str, "Pixel IFOV, e.g. 0.227mrad.", SENSOR),
    OptionSpec("hfov", str, "Horizontal field of view, e.g. 12deg.", SENSOR),
    OptionSpec("pixels", int, "Pixels across --hfov, e.g. 640.", SENSOR),
    OptionSpec(
        "projection",
        str,
        "How --hfov over --pixels gives the IFOV: "
        f"{_names(FIELD_OF_VIEW_PROJECTIONS)} (default angular: HFOV / pixels, datasheets; "
        "rectilinear: 2 tan(HFOV/2) / pixels).",
        SENSOR,
    ),
    OptionSpec(
        "pixel_density",
        str,
        f"EN 62676-4 pixel density from --hfov: {_names(PIXEL_DENSITY_DEFINITIONS)} (default "
        "plane: scene width 2R tan(HFOV/2); arc: R · HFOV).",
        SENSOR,
    ),
    OptionSpec("aperture", str, "Lens aperture diameter for diffraction, e.g. 75mm.", SENSOR),
    OptionSpec("f_number", float, "Lens F-number: aperture = focal length / F#.", SENSOR),
    OptionSpec("wavelength", str, "Wavelength for diffraction, e.g. 10um.", SENSOR),
    OptionSpec("blur", str, "Angular std. dev. of a Gaussian optics blur, e.g. 0.05mrad.", SENSOR),
    OptionSpec("critical_dimension", str, "Target critical dimension, e.g. 2.3m.", TARGET),
    OptionSpec("criterion", str, f"Criteria set: {_names(CRITERIA)} (default johnson).", MODEL),
    OptionSpec(
        "n50", str, "User-defined N50 cycles for detection,recognition,identification.", MODEL
    ),
    OptionSpec("transform", str, f"Transform: {_names(TRANSFORMS)} (default ttpf).", MODEL),
    OptionSpec("bound", str, f"c2nveo bound: {_names(C2NVEO_BOUNDS)}.", MODEL),
    OptionSpec("scr", float, "Signal-to-clutter ratio (schmieder-weathersby).", SCENE),
    OptionSpec(
        "clutter",
        str,
        f"Clutter region (schmieder-weathersby): {_names(CLUTTER_REGIONS)}.",
        SCENE,
    ),
    OptionSpec("band", str, f"Sensor band: {_names(BANDS)} or e.g. 8-12um.", SENSOR),
    OptionSpec("target_temperature", str, "Target temperature, e.g. 305K or 32degC.", SCENE),
    OptionSpec("background_temperature", str, "Background temperature, e.g. 295K.", SCENE),
    OptionSpec("emissivity", float, "Target emissivity in [0, 1] (default 1).", SCENE),
    OptionSpec(
        "background_emissivity", float, "Background emissivity in [0, 1] (default 1).", SCENE
    ),
    OptionSpec(
        "clutter_std",
        str,
        "Background temperature spread (clutter), e.g. 2K; gives the SCR.",
        SCENE,
    ),
    OptionSpec("extinction", str, "Path extinction, e.g. 0.4/km (Np/km) or 1.7dB/km.", PATH),
    OptionSpec(
        "obscurant", str, f"Table 7.1 obscurant[:low|nominal|high]: {_names(OBSCURANTS)}.", PATH
    ),
    OptionSpec("visibility", str, "Visibility (visible band), e.g. 7.5km.", PATH),
    OptionSpec(
        "visibility_convention",
        str,
        f"Visibility convention: {_names(VISIBILITY_CONVENTIONS)}.",
        PATH,
    ),
    OptionSpec(
        "noise_model", str, f"Noise model: {_names(NOISE_MODELS)} (default variance-sum).", NOISE
    ),
    OptionSpec("netd", str, "Thermal camera's NETD, e.g. 50mK (needs --delta-t).", NOISE),
    OptionSpec(
        "netd_temperature",
        str,
        "Temperature at which the NETD is quoted, to turn the target and background "
        "temperatures into a ΔT (default 300K).",
        NOISE,
    ),
    OptionSpec("delta_t", str, "Target-background temperature difference, e.g. 2K.", NOISE),
    OptionSpec("nec", float, "TV camera's noise-equivalent contrast, e.g. 0.01.", NOISE),
    OptionSpec("contrast", float, "Target contrast for --nec, e.g. 0.3.", NOISE),
    OptionSpec(
        "target_area",
        str,
        "Area of the target as seen, for its pixels (default: dimension²).",
        NOISE,
    ),
    OptionSpec(
        "mrtd",
        str,
        "MRTD curve CSV (frequency [cycles/mrad], mrtd [K]); needs --delta-t.",
        NOISE,
    ),
    OptionSpec(
        "semantics",
        str,
        f"Acquisition semantics: {_names(ACQUISITION_SEMANTICS)} (default nested).",
        MODEL,
    ),
    OptionSpec(
        "probability",
        str,
        "Probability, or several separated by commas, e.g. 0.5,0.8.",
        MODEL,
    ),
)
"""Every option of :func:`~targetacq.services.range_case.range_setup` but ``example`` (a flag,
added by :func:`range_case_options`) and ``default_probability`` (the command's own)."""

_NOT_OPTIONS = {"example", "default_probability"}

F = TypeVar("F", bound=Callable[..., Any])


def _parameter(spec: OptionSpec) -> inspect.Parameter:
    return inspect.Parameter(
        spec.name,
        inspect.Parameter.KEYWORD_ONLY,
        default=None,
        annotation=Annotated[
            spec.kind | None,
            typer.Option(spec.flag, help=spec.help, rich_help_panel=spec.panel),
        ],
    )


def range_case_options(function: F) -> F:
    """Decorate a typer command so that it takes every range-case option.

    The options reach ``function`` as one keyword argument, ``case_options``: a dict of every
    :data:`RANGE_CASE_OPTIONS` name and ``example`` → the value given (None, or False for
    ``example``, when not given), ready for ``range_setup(**case_options, ...)``.
    """
    signature = inspect.signature(function, eval_str=True)
    own = [p for p in signature.parameters.values() if p.name != "case_options"]
    added = [_parameter(spec) for spec in RANGE_CASE_OPTIONS]
    added.append(
        inspect.Parameter(
            "example",
            inspect.Parameter.KEYWORD_ONLY,
            default=False,
            annotation=Annotated[
                bool,
                typer.Option(
                    "--example",
                    help="Use the bundled example camera and target.",
                    rich_help_panel=SENSOR,
                ),
            ],
        )
    )
    names = [p.name for p in added]

    @functools.wraps(function)
    def command(**kwargs: Any) -> Any:
        case_options = {name: kwargs.pop(name) for name in names}
        return function(**kwargs, case_options=case_options)

    command.__signature__ = signature.replace(  # type: ignore[attr-defined]
        parameters=[*own, *added]
    )
    return command  # type: ignore[return-value]


def option_coverage() -> tuple[set[str], set[str]]:
    """The keywords of ``range_setup`` that have no option here, and the options here that
    ``range_setup`` does not take (both empty: a test keeps them so)."""
    wanted = set(inspect.signature(range_setup).parameters) - _NOT_OPTIONS
    have = {spec.name for spec in RANGE_CASE_OPTIONS}
    return wanted - have, have - wanted
