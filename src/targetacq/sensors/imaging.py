"""What every imaging sensor shares: its resolution model and its emissivity lookup."""

from __future__ import annotations

from typing import Any

from targetacq.physics import optics, radiometry


def cycle_angle(sensor: Any) -> float:
    """Angle of one resolvable cycle of a scenario sensor [rad].

    Sampling (2·IFOV) against the diffraction limit of the aperture at the band's centre
    wavelength, when an aperture is given (:func:`targetacq.physics.optics.resolvable_cycle_angle`).
    """
    wavelength = sum(sensor.limits) / 2 if sensor.aperture is not None else None
    return float(
        optics.resolvable_cycle_angle(
            sensor.pixel_ifov, wavelength=wavelength, aperture=sensor.aperture
        )
    )


def emissivity(thing: Any, band: tuple[float, float]) -> float:
    """Emissivity of a target or background record in a band: given, from its Table 6.1
    material, or 1 (a blackbody)."""
    if thing.emissivity is not None:
        return float(thing.emissivity)
    if thing.material is not None:
        return radiometry.material_emissivity(thing.material, band)
    return 1.0


def no_noise(sensor: Any, seen: Any) -> float:
    """A sensor type without a noise model of its own: no sensor noise (0 W/m²)."""
    return 0.0


def unit_path_contrast(sensor: Any, seen: Any) -> float:
    """A sensor type without a reference contrast of its own: σ_path = 1 (used only with a
    sensor noise, :func:`targetacq.physics.detector_noise.contrast_snr`)."""
    return 1.0


def one_row(sensor: Any) -> list[Any]:
    """A sensor that is one row of the array core: itself."""
    return [sensor]


def reflective_requirements(
    scenario: Any, label: str, article: str, emitting: bool = False
) -> list[str]:
    """What a scenario lacks for sensors that see reflected light (TV, SWIR), each problem
    located (``table.key: what``).

    ``label`` names the type in the messages ("TV", "SWIR") and ``article`` the sensor ("a TV
    camera"); an ``emitting`` type (SWIR: reflected plus emitted) also needs the temperatures.
    """
    bg = scenario.background
    temperature = ("temperature",) if emitting else ()
    problems = [
        f"background.{key}: required with {label} sensors"
        for key in ("irradiance", "reflectance", *temperature)
        if getattr(bg, key) is None
    ]
    problems += [
        f"targets[{k}].{key}: {label} sensors need a {key} for every target"
        for k, t in enumerate(scenario.targets)
        for key in ("reflectance", *temperature)
        if getattr(t, key) is None
    ]
    problems += [
        f"{where}: a table of bands is for colour cameras; {article} takes one value"
        for where, value in [
            ("background.reflectance", bg.reflectance),
            ("background.irradiance", bg.irradiance),
            *[(f"targets[{k}].reflectance", t.reflectance) for k, t in enumerate(scenario.targets)],
        ]
        if isinstance(value, dict)
    ]
    if bg.clutter_std is not None:
        problems.append(
            f"background.clutter_std: a temperature spread; for {label} sensors give clutter or scr"
        )
    if bg.terrain is not None:
        problems.append(
            "background.terrain: terrain clutter is given by class temperatures: thermal "
            "sensors only"
        )
    return problems
