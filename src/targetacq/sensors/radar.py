"""Pulse radars (Sonesson 2004 §9.4.3): the three factors of the model, for an active sensor.

The kernels are in :mod:`targetacq.physics.radar_equation`; the core computes a radar's pairs in
:mod:`targetacq.core.active`:

- **resolution**: the cells on target, the critical dimension over the resolution cell of
  Eqs. (9.1) (along track, the antenna's beamwidth) and (9.2) (range, the pulse length);
- **clutter**: the signal-to-clutter ratio ``σ / (σ⁰ A)`` of the target's radar cross-section σ
  against the ground's backscatter σ⁰ over the resolution cell's area A (a power ratio);
- **noise**: the radar equation's SNR (``K σ τ² / R⁴``, the path travelled twice), with the
  path's rain attenuation at the radar's frequency (ITU-R P.838-3);
- **probabilities**: detection from the signal-to-interference ratio ``1/(1/SNR + 1/SCR)`` and
  the false-alarm probability by the radar's detector model (Albersheim's equation by default);
  recognition and identification from the cells on target through the TTPF with the project's
  radar criteria (below), never more likely than detection.

The project's assumptions, stated:

- the clutter in the resolution cell acts as noise (it adds to the receiver noise in power);
- a radar here scans all around: every target is in its view (no field of view);
- the optical extinctions of the scenario (extinction, obscurant, visibility, clouds) do not
  apply at radar wavelengths; rain (``atmosphere.rain_rate``) does, the same all along the slant
  path (an airborne radar above the rain is attenuated too much), with the coefficients of a
  level path (elevation 0) in the radar's polarisation;
- recognition and identification need, at P = 0.5, 8 and 12.8 cells across the critical
  dimension (``radar.recognition_cells``, ``radar.identification_cells``): Johnson's 4 and 6.4
  cycles at two resolution cells per cycle, as a pixel samples an image; no published criteria
  for radar cells exist that we know of, and the values can be set per radar.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.sensors.signature import Signature


def signature(sensor: Any, background: Any, targets: Sequence[Any]) -> Any:
    """The targets' radar cross-sections [m²] against no background signal."""
    rcs = np.array([t.rcs for t in targets], dtype=float)
    return Signature(rcs, 0.0, None)


def cycle_angle(sensor: Any) -> float:
    """The beamwidth [rad]: the along-track cell of Eq. (9.1) is ``2 R sin(θ_a / 2)``."""
    return float(sensor.radar.beamwidth)


def requirements(scenario: Any) -> list[str]:
    """What a scenario lacks for radars, each problem located (``table.key: what``)."""
    problems = [
        f"targets[{k}].rcs: radars need a radar cross-section for every target (e.g. '10 m^2')"
        for k, t in enumerate(scenario.targets)
        if t.rcs is None
    ]
    if scenario.atmosphere.rain_rate is not None:
        problems += [
            f"sensors[{k}].radar.frequency: the rain attenuation (ITU-R P.838-3) is given for "
            f"1 to 1000 GHz; got {s.radar.frequency / 1e9:g} GHz"
            for k, s in enumerate(scenario.sensors)
            if s.radar is not None and not 1e9 <= s.radar.frequency <= 1e12
        ]
    if scenario.background.sigma0 is None:
        problems.append(
            "background.sigma0: radars need the ground's backscatter coefficient (e.g. '-20 dB')"
        )
    return problems
