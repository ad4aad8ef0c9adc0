"""What every imaging sensor shares: its resolution model and its emissivity lookup."""

from __future__ import annotations

from typing import Any

from targetacq import optics, radiometry


def cycle_angle(sensor: Any) -> float:
    """Angle of one resolvable cycle of a scenario sensor [rad].

    Sampling (2·IFOV) against the diffraction limit of the aperture at the band's centre
    wavelength, when an aperture is given (:func:`targetacq.optics.resolvable_cycle_angle`).
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


def one_row(sensor: Any) -> list[Any]:
    """A sensor that is one row of the array core: itself."""
    return [sensor]
