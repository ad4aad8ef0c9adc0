"""Colour cameras: one conceptual model per colour band, merged as correlated (§9.4.2).

Sonesson (2004) §9.4.2 proposes a conceptual sensor model for each colour band (red, green,
blue), merged "with something like the methods presented in chapter 8". A colour camera here is
compiled into one row per band: each row is a TV camera (:mod:`targetacq.sensors.tv`) whose
target and background reflectances, irradiance and noise are those of its band, and which shares
everything else — position, pointing, optics, field of view and path — with the other bands.

Merging. The bands are not independent sensors: they see the same scene at the same moment
through the same optics, and one observer (or one detector chain) looks at the one picture. The
independent-sensor rule of Eq. (8.4), ``1 − Π(1 − p_b)``, would count the same look three times
(three identical bands of P = 0.5 would report 0.875). The project's rule takes the bands as
completely dependent (comonotone): a target is found in the colour picture exactly when it is
found in the band where it is easiest to find, so ``P = max_b p_b``
(:func:`targetacq.acquisition.fusion.fuse_groups`). This is the Fréchet–Hoeffding upper bound of the
dependence between events, the opposite extreme of Eq. (8.4); with it three identical bands give
the single band's probability exactly, and a target that differs from its background in one
band only is found through that band. Over time (the step API and ``simulate``) the bands of one
camera draw their outcomes from one random stream, the same coupling.

Assumptions stated: the bands share the visible band's extinction (one path, narrow bands); a
colour band's contrast acts through the camera's noise (``nec`` times the band's background
exitance), which a colour camera must therefore have; a clutter given as an SCR or a region is
the same for every band.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.physics import radiometry
from targetacq.sensors.signature import Signature


def band_value(value: Any, band: str) -> Any:
    """A band's entry of a per-band table, or the one value that holds for every band."""
    return value[band] if isinstance(value, dict) else value


def signature(sensor: Any, background: Any, targets: Sequence[Any]) -> Any:
    """Reflected exitances of the targets and the background in the row's band."""
    band = sensor.bands[0]
    irradiance = band_value(background.irradiance, band)
    m_b = float(radiometry.reflected_exitance(band_value(background.reflectance, band), irradiance))
    reflectance = np.array([band_value(t.reflectance, band) for t in targets], dtype=float)
    m_t = np.asarray(radiometry.reflected_exitance(reflectance, irradiance))
    return Signature(m_t, m_b, None)


def noise_equivalent(sensor: Any, seen: Any) -> float:
    """``NEC · M_background`` of the band [W/m²]; 0 without an NEC."""
    if sensor.nec is None:
        return 0.0
    return float(sensor.nec * seen.background)


def rows(sensor: Any) -> list[Any]:
    """The camera as one sensor per band, named ``camera.band``, each with its one band."""
    return [
        sensor.model_copy(update={"name": f"{sensor.name}.{band}", "bands": [band]})
        for band in sensor.bands
    ]


def requirements(scenario: Any) -> list[str]:
    """What a scenario lacks for colour cameras, each problem located (``table.key: what``)."""
    bg = scenario.background
    bands = list(
        dict.fromkeys(b for s in scenario.sensors if s.type == "colour" for b in s.bands or [])
    )
    problems = []

    def check(value: Any, where: str, what: str) -> None:
        if value is None:
            problems.append(f"{where}: colour cameras need {what}")
        elif isinstance(value, dict):
            missing = [b for b in bands if b not in value]
            unknown = [b for b in value if b not in bands]
            if missing:
                problems.append(
                    f"{where}: no value for band {missing[0]!r} of the colour cameras "
                    f"(bands: {', '.join(bands)})"
                )
            elif unknown:  # a typo, or a band no camera has: it would be silently unused
                problems.append(
                    f"{where}.{unknown[0]}: {unknown[0]!r} is not a band of the colour cameras "
                    f"(bands: {', '.join(bands)})"
                )

    check(bg.irradiance, "background.irradiance", "the irradiance (one value or one per band)")
    check(bg.reflectance, "background.reflectance", "the reflectance (one value or one per band)")
    for k, t in enumerate(scenario.targets):
        check(t.reflectance, f"targets[{k}].reflectance", "a reflectance per band")
    for k, s in enumerate(scenario.sensors):
        if s.type == "colour" and not (s.nec or 0.0) > 0:
            problems.append(
                f"sensors[{k}].nec: a colour camera needs its noise-equivalent contrast (> 0): "
                "a band's contrast acts through the camera's noise (without it, a target that "
                "matches its background in every band would still be seen)"
            )
    for band in bands:
        if problems:
            break
        level = band_value(bg.reflectance, band) * band_value(bg.irradiance, band)
        if not level > 0:
            problems.append(
                f"background.irradiance: band {band!r} has no background light (reflectance x "
                "irradiance is 0): the camera's noise is relative to it; give both > 0"
            )
    for key in ("clutter_std", "terrain", "image"):
        if getattr(bg, key) is not None:
            problems.append(
                f"background.{key}: not for colour cameras; give clutter (a region) or scr"
            )
    return problems
