"""Laser radars (Sonesson 2004 §9.4.4): three-dimensional pictures, with the model's factors.

The kernels are in :mod:`targetacq.physics.laser_radar_equation`; the core computes a laser radar's
pairs in
:mod:`targetacq.core.active`:

- **resolution**: as an imager's, from the detector spacing (the IFOV; two pixels a cycle), so
  the cycles on target and the transforms are those of the imaging sensors;
- **clutter**: a 3-D measure, the target's visible height over the background's relief spread
  combined with the range resolution ``c t / 2``
  (:func:`targetacq.physics.laser_radar_equation.relief_scr`);
- **noise**: the atmosphere of Eq. (7.7) over the two-way path (the return travels the path
  twice), combined in variance with the receiver's SNR from the range equation of an extended
  Lambertian target (:func:`targetacq.physics.laser_radar_equation.received_power`) over its
  noise-equivalent
  power.

The project's assumptions are stated in :mod:`targetacq.physics.laser_radar_equation`; here, in
addition: the target's reflectance (``targets.reflectance``) is at the laser's wavelength, and the
sensor's ``band`` holds that wavelength (for the path's extinction).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.physics import atmosphere
from targetacq.sensors.signature import Signature


def signature(sensor: Any, background: Any, targets: Sequence[Any]) -> Any:
    """The targets' reflectances at the laser's wavelength (the range equation's ρ)."""
    reflectance = np.array([t.reflectance for t in targets], dtype=float)
    return Signature(reflectance, 0.0, None)


def requirements(scenario: Any) -> list[str]:
    """What a scenario lacks for laser radars, each problem located (``table.key: what``).

    A ``laser.nep`` given as 0 W is accepted, as documented (a receiver without noise: the
    laser radar's SNR is its two-way path's alone), and said: a ``UserWarning`` naming it,
    since a zero typed for a receiver's noise may as well be a slip.
    """
    for k, s in enumerate(scenario.sensors):
        laser = getattr(s, "laser", None)
        if laser is None or "nep" not in laser.model_fields_set:
            continue
        if s.type == "laser_radar" and laser.nep == 0:
            warnings.warn(
                f"sensors[{k}].laser.nep = 0 W: a receiver without noise, so the laser "
                f"radar {s.name!r} sees only its path's noise (give the receiver's "
                "noise-equivalent power, e.g. 5 nW, for its own)",
                UserWarning,
                stacklevel=2,
            )
    problems = [
        f"targets[{k}].reflectance: laser radars need one reflectance per target (at the "
        "laser's wavelength)"
        for k, t in enumerate(scenario.targets)
        if t.reflectance is None or isinstance(t.reflectance, dict)
    ]
    if scenario.background.relief_std is None:
        problems.append(
            "background.relief_std: laser radars need the ground's relief spread (the 3-D "
            "clutter, e.g. '0.3 m'; 0 for flat open ground)"
        )
    atm = scenario.atmosphere
    for k, s in enumerate(scenario.sensors):
        if s.type != "laser_radar" or s.band is None:
            continue
        if atm.visibility is not None:
            problems.append(
                "atmosphere.visibility: gives the visible-band extinction; with laser radars "
                "give extinction (at the laser's wavelength)"
            )
        if atm.obscurant is not None:
            try:
                atmosphere.extinction_for_band(s.limits, obscurant=atm.obscurant)
            except ValueError as error:
                problems.append(
                    f"atmosphere.obscurant: {error}; for the laser radar sensors[{k}] (band "
                    f"{s.band}) give atmosphere.extinction"
                )
    problems += [
        f"sensors[{k}].band: a laser radar needs its band (the laser's wavelength, e.g. "
        "'1.5-1.6 um')"
        for k, s in enumerate(scenario.sensors)
        if s.type == "laser_radar" and s.band is None
    ]
    return problems
