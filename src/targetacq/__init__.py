"""targetacq: probabilities of detection, recognition and identification for imaging sensors.

An implementation of the probabilistic conceptual sensor model of Sonesson (2004): geometry →
cycles on target, clutter → SCR, then Johnson-style transforms → probabilities, fused over
sensors. SI units throughout (m, rad, K, s). This module only re-exports the public API.

The names are imported on first use (PEP 562): ``import targetacq`` costs almost nothing, and
``targetacq.dri_ranges`` imports :mod:`targetacq.core.ranges` (NumPy, SciPy) when first looked up.

Examples
--------
>>> import targetacq
>>> targetacq.__version__
'0.1.0'
>>> targetacq.TASKS
('detection', 'orientation', 'recognition', 'identification')
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

_EXPORTS: dict[str, tuple[str, ...]] = {
    "acquisition.probabilities": (
        "Acquisition",
        "Clutter",
        "acquisition_probabilities",
        "effect_probability",
        "probability",
    ),
    "physics.atmosphere": (
        "extinction_from_visibility",
        "obscurant_extinction",
        "path_transmittance",
        "snr_from_transmittance",
        "transmittance",
    ),
    "physics.bands": ("BANDS",),
    "base.bundled": ("example_path",),
    "physics.clutter": (
        "image_clutter",
        "signal_to_clutter_ratio",
        "terrain_clutter",
    ),
    "run.design": (
        "required_focal_length",
        "required_ifov",
    ),
    "acquisition.criteria": (
        "CRITERIA",
        "TASKS",
        "Criterion",
        "get_criterion",
        "register_criterion",
        "unregister_criterion",
    ),
    "acquisition.calibration": (
        "CriterionFit",
        "fit_criterion",
    ),
    "acquisition.fusion": (
        "central_level_bounds",
        "fuse",
        "fuse_groups",
    ),
    "physics.geometry": (
        "critical_dimension",
        "projected_extents",
        "slant_range",
        "solid_angle",
    ),
    "acquisition.path_noise": (
        "NOISE_MODELS",
        "effective_scr",
        "noise_n50_factor",
    ),
    "physics.line_of_sight": ("line_of_sight",),
    "physics.optics": (
        "cycles_on_target",
        "diffraction_angle",
        "diffraction_spot",
        "field_of_view",
        "gaussian_psf",
        "ifov",
        "ifov_from_field_of_view",
        "pixels_per_metre",
        "range_for_cycles",
        "range_for_pixel_density",
        "resolvable_cycle_angle",
    ),
    "physics.radiometry": (
        "band_exitance",
        "spectral_exitance",
    ),
    "core.ranges": ("RangeCase", "dri_ranges"),
    "run.scene": (
        "Scene",
        "SceneAcquisition",
        "scene_acquisition",
    ),
    "run.simulation": ("Simulation",),
    "run.studies": ("sweep",),
    "acquisition.transforms": (
        "TRANSFORMS",
        "c2nveo",
        "c2nveo_inverse",
        "clutter_region",
        "inverse_transform",
        "schmieder_weathersby",
        "schmieder_weathersby_inverse",
        "transform",
        "ttpf",
        "ttpf_inverse",
    ),
}
"""Submodule (of ``targetacq``) → the names this package re-exports from it."""

_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = [
    "BANDS",
    "CRITERIA",
    "NOISE_MODELS",
    "TASKS",
    "TRANSFORMS",
    "Acquisition",
    "Clutter",
    "Criterion",
    "CriterionFit",
    "RangeCase",
    "Scene",
    "SceneAcquisition",
    "Simulation",
    "acquisition_probabilities",
    "band_exitance",
    "c2nveo",
    "c2nveo_inverse",
    "central_level_bounds",
    "clutter_region",
    "critical_dimension",
    "cycles_on_target",
    "diffraction_angle",
    "diffraction_spot",
    "dri_ranges",
    "effect_probability",
    "effective_scr",
    "example_path",
    "extinction_from_visibility",
    "field_of_view",
    "fit_criterion",
    "fuse",
    "fuse_groups",
    "gaussian_psf",
    "get_criterion",
    "ifov",
    "ifov_from_field_of_view",
    "image_clutter",
    "inverse_transform",
    "line_of_sight",
    "noise_n50_factor",
    "obscurant_extinction",
    "path_transmittance",
    "pixels_per_metre",
    "probability",
    "projected_extents",
    "range_for_cycles",
    "range_for_pixel_density",
    "register_criterion",
    "required_focal_length",
    "required_ifov",
    "resolvable_cycle_angle",
    "scene_acquisition",
    "schmieder_weathersby",
    "schmieder_weathersby_inverse",
    "signal_to_clutter_ratio",
    "slant_range",
    "snr_from_transmittance",
    "solid_angle",
    "spectral_exitance",
    "sweep",
    "terrain_clutter",
    "transform",
    "transmittance",
    "ttpf",
    "ttpf_inverse",
    "unregister_criterion",
]

if TYPE_CHECKING:  # the same names, for type checkers and IDEs (a test keeps them equal)
    from targetacq.acquisition.calibration import (
        CriterionFit,
        fit_criterion,
    )
    from targetacq.acquisition.criteria import (
        CRITERIA,
        TASKS,
        Criterion,
        get_criterion,
        register_criterion,
        unregister_criterion,
    )
    from targetacq.acquisition.fusion import (
        central_level_bounds,
        fuse,
        fuse_groups,
    )
    from targetacq.acquisition.path_noise import (
        NOISE_MODELS,
        effective_scr,
        noise_n50_factor,
    )
    from targetacq.acquisition.probabilities import (
        Acquisition,
        Clutter,
        acquisition_probabilities,
        effect_probability,
        probability,
    )
    from targetacq.acquisition.transforms import (
        TRANSFORMS,
        c2nveo,
        c2nveo_inverse,
        clutter_region,
        inverse_transform,
        schmieder_weathersby,
        schmieder_weathersby_inverse,
        transform,
        ttpf,
        ttpf_inverse,
    )
    from targetacq.base.bundled import (
        example_path,
    )
    from targetacq.core.ranges import (
        RangeCase,
        dri_ranges,
    )
    from targetacq.physics.atmosphere import (
        extinction_from_visibility,
        obscurant_extinction,
        path_transmittance,
        snr_from_transmittance,
        transmittance,
    )
    from targetacq.physics.bands import (
        BANDS,
    )
    from targetacq.physics.clutter import (
        image_clutter,
        signal_to_clutter_ratio,
        terrain_clutter,
    )
    from targetacq.physics.geometry import (
        critical_dimension,
        projected_extents,
        slant_range,
        solid_angle,
    )
    from targetacq.physics.line_of_sight import (
        line_of_sight,
    )
    from targetacq.physics.optics import (
        cycles_on_target,
        diffraction_angle,
        diffraction_spot,
        field_of_view,
        gaussian_psf,
        ifov,
        ifov_from_field_of_view,
        pixels_per_metre,
        range_for_cycles,
        range_for_pixel_density,
        resolvable_cycle_angle,
    )
    from targetacq.physics.radiometry import (
        band_exitance,
        spectral_exitance,
    )
    from targetacq.run.design import (
        required_focal_length,
        required_ifov,
    )
    from targetacq.run.scene import (
        Scene,
        SceneAcquisition,
        scene_acquisition,
    )
    from targetacq.run.simulation import (
        Simulation,
    )
    from targetacq.run.studies import (
        sweep,
    )


def __getattr__(name: str) -> Any:
    """Import a re-exported name's submodule on first use and keep the name here."""
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module 'targetacq' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"targetacq.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
