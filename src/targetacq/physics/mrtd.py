"""MRTD-limited resolution: a thermal imager resolves a target to the bar frequency at which the
target's apparent temperature difference equals the minimum resolvable temperature difference.

This is the static-performance reading of STANAG 4347 and of the NVL static performance model
(J. A. Ratches, "Static performance model for thermal imaging systems", Opt. Eng. 15(6)
(1976) 525): the MRTD curve ``MRTD(f)`` of the sensor (from the bench, STANAG 4349 four-bar
measurement, or from a formula) is intersected with the temperature difference the target
presents at the aperture, ``τ(R)·ΔT``; the frequency ``f*`` of the intersection [cycles/rad] times
the angle the critical dimension subtends, ``Dc / R`` [rad], is the number of resolved cycles

    N(R) = f*(τ(R)·ΔT) · Dc / R,

which then goes through the same Johnson-style transforms as the geometric cycles of
:func:`targetacq.physics.optics.cycles_on_target`.

Three parts:

- :class:`MrtdCurve`: a tabulated curve, read from a bench CSV (:meth:`MrtdCurve.from_csv`) or
  sampled from the parametric formula (:meth:`MrtdCurve.from_parametric`);
- the curve as a function and its exact inverse (:func:`mrtd`, :func:`resolved_frequency`) and
  the resolved cycles (:func:`mrtd_cycles`), array-API kernels that broadcast;
- a published formula for the MRTD of a staring imager from its NETD, its system MTF and the
  observer's integration (:func:`parametric_mrtd`), with the system MTF it needs
  (:func:`system_mtf`, a product of the components of :mod:`targetacq.physics.mtf`, whose
  :func:`diffraction_mtf`, :func:`detector_mtf` and :func:`blur_mtf` are re-exported here).

Units: spatial frequency in cycles/rad inside (SI, like every kernel), cycles/mrad in the bench
file (the unit bench curves are printed in); temperatures in kelvin.

NaN in any array input gives NaN out (scalars too), and never raises; values out of range
(a negative range, a transmittance above 1, ...) raise ``ValueError`` for the whole call, naming
the input and the valid range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.inputs import read_input_text
from targetacq.physics.mtf import blur_mtf, detector_mtf, diffraction_mtf

__all__ = [
    "DEFAULT_EYE_INTEGRATION_TIME",
    "DEFAULT_FRAME_RATE",
    "DEFAULT_NOISE_BANDWIDTH_DWELL",
    "DEFAULT_SNR_THRESHOLD",
    "MRTD_CONSTANT",
    "MrtdCurve",
    "blur_mtf",
    "detector_mtf",
    "diffraction_mtf",
    "mrtd",
    "mrtd_cycles",
    "parametric_mrtd",
    "resolved_frequency",
    "system_mtf",
]

MRTD_CONSTANT = math.pi**2 / (4.0 * math.sqrt(14.0))
"""``π² / (4√14) ≈ 0.6594``, the constant of the four-bar MRTD formula (:func:`parametric_mrtd`)."""

DEFAULT_SNR_THRESHOLD = 2.5
"""Observer's threshold signal-to-noise ratio for resolving the bars [-] (project default)."""

DEFAULT_EYE_INTEGRATION_TIME = 0.1
"""Eye integration time [s] (project default)."""

DEFAULT_FRAME_RATE = 30.0
"""Frame rate [Hz] (project default)."""

DEFAULT_NOISE_BANDWIDTH_DWELL = 0.5
"""``Δf_R · τ_d`` of a staring pixel whose NETD is quoted in the bandwidth ``1/(2 t_int)`` of
its integration time ``t_int = τ_d`` [-]."""

_PER_MRAD = 1000.0  # a bench frequency in cycles/mrad is 1000 × that in cycles/rad


# --------------------------------------------------------------------------------------------
# Checks that keep NaN as NaN (scalars too) and raise for out-of-range values.


def _unit_interval(name: str, value: Array, xp: Any) -> None:
    _arrays.require_where(name, value, (value < 0) | (value > 1), xp, "in [0, 1]")


# --------------------------------------------------------------------------------------------
# The tabulated curve.


def _as_floats(values: Any, name: str) -> tuple[float, ...]:
    try:
        return tuple(float(v) for v in values)
    except (TypeError, ValueError):
        raise ValueError(f"MrtdCurve: {name} must be a sequence of numbers") from None


@dataclass(frozen=True)
class MrtdCurve:
    """A tabulated MRTD curve: MRTD [K] against bar spatial frequency [cycles/rad].

    Between the tabulated points :func:`mrtd` interpolates ln(MRTD) linearly in frequency; it is
    +inf above the last frequency (the cut-off: the bench resolved no finer bars) and
    proportional to frequency below the first one (see :func:`mrtd`).

    Attributes
    ----------
    frequency : tuple of float
        Bar spatial frequency [cycles/rad], > 0, strictly ascending, at least two.
    mrtd : tuple of float
        MRTD at each frequency [K], > 0, non-decreasing.
    provenance : str
        Where the numbers come from (the file and its ``#`` header, or the formula and its
        parameters); not part of equality.

    Raises
    ------
    ValueError
        Naming the column and the row (1-based) that breaks a rule above.

    Examples
    --------
    >>> curve = MrtdCurve(frequency=(500.0, 1000.0, 1500.0), mrtd=(0.05, 0.1, 0.4))
    >>> curve.cutoff
    1500.0
    >>> MrtdCurve(frequency=(500.0, 400.0), mrtd=(0.05, 0.1))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: MrtdCurve: column 'frequency' must be strictly ascending: row 2 (400 ...
    """

    frequency: tuple[float, ...]
    mrtd: tuple[float, ...]
    provenance: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        frequency = _as_floats(self.frequency, "frequency")
        values = _as_floats(self.mrtd, "mrtd")
        object.__setattr__(self, "frequency", frequency)
        object.__setattr__(self, "mrtd", values)
        if len(frequency) != len(values):
            raise ValueError(
                f"MrtdCurve: columns 'frequency' ({len(frequency)} rows) and 'mrtd' "
                f"({len(values)} rows) must have the same length"
            )
        if len(frequency) < 2:
            raise ValueError(f"MrtdCurve: needs at least 2 rows, got {len(frequency)}")
        for column, numbers, unit in (
            ("frequency", frequency, "cycles/rad"),
            ("mrtd", values, "K"),
        ):
            for row, number in enumerate(numbers, start=1):
                if not math.isfinite(number) or number <= 0:
                    raise ValueError(
                        f"MrtdCurve: column {column!r} must be finite and > 0 {unit}, "
                        f"row {row} is {number:g}"
                    )
        for row in range(1, len(frequency)):
            if frequency[row] <= frequency[row - 1]:
                raise ValueError(
                    "MrtdCurve: column 'frequency' must be strictly ascending: "
                    f"row {row + 1} ({frequency[row]:g} cycles/rad) is not above "
                    f"row {row} ({frequency[row - 1]:g} cycles/rad)"
                )
            if values[row] < values[row - 1]:
                raise ValueError(
                    "MrtdCurve: column 'mrtd' must be non-decreasing in frequency: "
                    f"row {row + 1} ({values[row]:g} K) is below row {row} ({values[row - 1]:g} K)"
                )

    @property
    def cutoff(self) -> float:
        """The last tabulated frequency [cycles/rad]: nothing finer is resolved."""
        return self.frequency[-1]

    @classmethod
    def from_csv(cls, path: str | Path) -> MrtdCurve:
        """Read a bench MRTD curve from a CSV file.

        The file has a header line naming the columns ``frequency`` (bar spatial frequency in
        **cycles/mrad**) and ``mrtd`` (in **K**), then one row per bar target; other columns
        are ignored, lines starting with ``#`` are comments (kept as the provenance), blank
        lines are skipped. Frequencies must be finite, > 0 and strictly ascending, MRTDs finite,
        > 0 and non-decreasing, at least two rows. The file is UTF-8 text (a byte-order mark,
        as spreadsheets write, is allowed) of at most 10 MB
        (:func:`targetacq.base.inputs.read_input_text`).

        Parameters
        ----------
        path : str or Path
            The file.

        Returns
        -------
        MrtdCurve
            Frequencies converted to cycles/rad.

        Raises
        ------
        ValueError
            Naming the file and the line: a missing column, a cell that is not a number,
            frequencies not ascending, a value <= 0 or not finite, fewer than two rows; or
            naming the file that cannot be read (missing, a folder or a device, too large, not
            UTF-8).

        Examples
        --------
        >>> import pathlib, tempfile
        >>> text = "# bench, 2 K\\nfrequency,mrtd\\n0.5,0.05\\n1.0,0.12\\n1.4,0.4\\n"
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = pathlib.Path(folder) / "bench.csv"
        ...     _ = path.write_text(text)
        ...     curve = MrtdCurve.from_csv(path)
        >>> curve.frequency, curve.mrtd
        ((500.0, 1000.0, 1400.0), (0.05, 0.12, 0.4))
        """
        return _parse_csv(read_input_text(path, "MRTD curve"), str(path))

    @classmethod
    def example(cls) -> MrtdCurve:
        """The bundled illustrative curve ``targetacq/data/example_mrtd.csv``.

        Generated by :func:`parametric_mrtd` for the example camera named in its header
        (640 × 512, 17 µm, 50 mm f/1.0, NETD 50 mK, 10 µm); not a measurement.

        Examples
        --------
        >>> curve = MrtdCurve.example()
        >>> len(curve.frequency), round(curve.cutoff)
        (14, 1400)
        """
        resource = resources.files("targetacq").joinpath("data").joinpath("example_mrtd.csv")
        return _parse_csv(resource.read_text("utf-8"), "targetacq/data/example_mrtd.csv")

    @classmethod
    def from_parametric(cls, frequencies: Array, **sensor: Any) -> MrtdCurve:
        """Sample :func:`parametric_mrtd` at the given frequencies.

        Parameters
        ----------
        frequencies : array_like
            Bar spatial frequencies [cycles/rad], > 0, strictly ascending, below the first zero
            of the system MTF (for a staring array, end them near the Nyquist frequency
            ``1 / (2 IFOV)``: the formula knows nothing of sampling).
        **sensor
            The keyword arguments of :func:`parametric_mrtd` (``netd``, ``ifov``, ``aperture``,
            ``wavelength``, ...).

        Returns
        -------
        MrtdCurve

        Examples
        --------
        >>> curve = MrtdCurve.from_parametric(
        ...     [500.0, 1000.0, 1400.0], netd=0.05, ifov=3.4e-4, aperture=0.05, wavelength=10e-6
        ... )
        >>> [round(m, 4) for m in curve.mrtd]
        [0.0138, 0.0373, 0.0741]
        """
        f = np.asarray(frequencies, dtype=np.float64).reshape(-1)
        values = np.asarray(parametric_mrtd(f, **sensor), dtype=np.float64).reshape(-1)
        for fi, mi in zip(f.tolist(), values.tolist(), strict=True):
            if not math.isfinite(mi):
                raise ValueError(
                    f"frequencies: {fi:g} cycles/rad is at or beyond the first zero of the "
                    "system MTF, where the MRTD formula is infinite"
                )
        parameters = ", ".join(f"{key}={value!r}" for key, value in sorted(sensor.items()))
        return cls(
            frequency=tuple(f.tolist()),
            mrtd=tuple(values.tolist()),
            provenance=f"parametric_mrtd({parameters})",
        )


def _parse_csv(text: str, name: str) -> MrtdCurve:
    comments: list[str] = []
    header: list[str] | None = None
    header_line = 0
    rows: list[tuple[int, float, float]] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line:
            continue
        if line.startswith("#"):
            comments.append(line[1:].strip())
            continue
        cells = [cell.strip() for cell in line.split(",")]
        if header is None:
            header = [cell.lower() for cell in cells]
            header_line = number
            for column, unit in (("frequency", "cycles/mrad"), ("mrtd", "K")):
                if column not in header:
                    raise ValueError(
                        f"{name}, line {number}: missing column {column!r} [{unit}] "
                        f"(the header names {', '.join(repr(c) for c in cells)})"
                    )
            continue
        if len(cells) != len(header):
            raise ValueError(
                f"{name}, line {number}: {len(cells)} cells, but the header on line "
                f"{header_line} names {len(header)} columns"
            )
        values = []
        for column, unit in (("frequency", "cycles/mrad"), ("mrtd", "K")):
            cell = cells[header.index(column)]
            try:
                value = float(cell)
            except ValueError:
                raise ValueError(
                    f"{name}, line {number}: column {column!r}: {cell!r} is not a number"
                ) from None
            if not math.isfinite(value) or value <= 0:
                raise ValueError(
                    f"{name}, line {number}: column {column!r} must be a finite number > 0 "
                    f"{unit}, got {cell}"
                )
            values.append(value)
        if rows:
            previous_line, previous_f, previous_m = rows[-1]
            if values[0] <= previous_f:
                raise ValueError(
                    f"{name}, line {number}: column 'frequency' must be strictly ascending: "
                    f"{values[0]:g} cycles/mrad is not above {previous_f:g} on line {previous_line}"
                )
            if values[1] < previous_m:
                raise ValueError(
                    f"{name}, line {number}: column 'mrtd' must be non-decreasing in frequency: "
                    f"{values[1]:g} K is below {previous_m:g} K on line {previous_line}"
                )
        rows.append((number, values[0], values[1]))
    if header is None:
        raise ValueError(f"{name}: no header line naming the columns 'frequency' and 'mrtd'")
    if len(rows) < 2:
        raise ValueError(f"{name}: needs at least 2 data rows (frequency, mrtd), found {len(rows)}")
    provenance = "\n".join([name, *comments])
    return MrtdCurve(
        frequency=tuple(f * _PER_MRAD for _, f, _ in rows),
        mrtd=tuple(m for _, _, m in rows),
        provenance=provenance,
    )


def _check_curve(curve: Any) -> MrtdCurve:
    if not isinstance(curve, MrtdCurve):
        raise TypeError(f"curve must be an MrtdCurve, got {type(curve).__name__}")
    return curve


def _tables(curve: MrtdCurve, xp: Any, dtype: Any) -> tuple[Array, Array, Array]:
    f = xp.asarray(curve.frequency, dtype=dtype)
    m = xp.asarray(curve.mrtd, dtype=dtype)
    return f, m, xp.log(m)


# --------------------------------------------------------------------------------------------
# The curve as a function and its inverse.


def _mrtd_law(frequency: Array, curve: MrtdCurve, xp: Any) -> Array:
    f_tab, m_tab, lnm_tab = _tables(curve, xp, frequency.dtype)
    n = len(curve.frequency)
    f_first, f_last, m_first = f_tab[0], f_tab[n - 1], m_tab[0]
    flat = xp.reshape(frequency, (-1,))
    # Clamp above the cut-off so that no exponential overflows in a branch that is not taken.
    clamped = xp.where(flat > f_last, f_last, flat)
    k = xp.clip(xp.searchsorted(f_tab, clamped, side="left"), 1, n - 1)
    f0, f1 = xp.take(f_tab, k - 1), xp.take(f_tab, k)
    l0, l1 = xp.take(lnm_tab, k - 1), xp.take(lnm_tab, k)
    inside = xp.exp(l0 + (clamped - f0) / (f1 - f0) * (l1 - l0))
    below = m_first * clamped / f_first
    out = xp.where(flat > f_last, xp.inf, xp.where(flat <= f_first, below, inside))
    return xp.reshape(out, frequency.shape)


def _frequency_law(delta_t: Array, curve: MrtdCurve, xp: Any) -> Array:
    f_tab, m_tab, lnm_tab = _tables(curve, xp, delta_t.dtype)
    n = len(curve.frequency)
    f_first, f_last = f_tab[0], f_tab[n - 1]
    m_first, m_last = m_tab[0], m_tab[n - 1]
    flat = xp.reshape(delta_t, (-1,))
    positive = xp.where(flat <= 0, m_first, flat)  # no log(0) or log(-x); NaN stays NaN
    # k - 1 is the last row with MRTD <= ΔT: the largest frequency with MRTD(f) = ΔT.
    k = xp.clip(xp.searchsorted(m_tab, positive, side="right"), 1, n - 1)
    f0, f1 = xp.take(f_tab, k - 1), xp.take(f_tab, k)
    l0, l1 = xp.take(lnm_tab, k - 1), xp.take(lnm_tab, k)
    step = l1 - l0
    step = xp.where(step > 0, step, 1.0)  # > 0 wherever the branch is taken
    inside = f0 + (xp.log(positive) - l0) / step * (f1 - f0)
    below = f_first * positive / m_first
    out = xp.where(flat >= m_last, f_last, xp.where(flat < m_first, below, inside))
    out = xp.where(flat <= 0, 0.0, out)
    return xp.reshape(out, delta_t.shape)


def mrtd(frequency: Array, curve: MrtdCurve) -> Any:
    """The MRTD of a tabulated curve at any bar frequency.

    The law between and beyond the tabulated points ``(f_i, M_i)``:

    - ``f_1 <= f <= f_n``: ``ln MRTD`` linear in ``f`` between neighbouring points,
      ``MRTD(f) = M_i · (M_{i+1}/M_i)^((f − f_i)/(f_{i+1} − f_i))`` (MRTD curves rise roughly
      exponentially towards the cut-off, so this is the interpolation that bends with them);
    - ``f > f_n``: +inf. The last tabulated frequency is taken as the bench's cut-off: bars
      finer than the finest the bench resolved are not resolved at any temperature difference;
    - ``0 <= f < f_1``: ``MRTD(f) = M_1 · f / f_1``, proportional to frequency as the classic
      formula is near ``f = 0`` (:func:`parametric_mrtd` with an MTF near 1). With it the
      resolved frequency (:func:`resolved_frequency`) is continuous and falls to 0 with the
      temperature difference, instead of jumping from ``f_1`` to nothing.

    The law is continuous, non-decreasing, and strictly increasing below ``f_1``.

    Parameters
    ----------
    frequency : array_like
        Bar spatial frequency [cycles/rad], >= 0.
    curve : MrtdCurve
        The sensor's curve.

    Returns
    -------
    array_like
        MRTD [K]; +inf above the cut-off; NaN where the frequency is NaN.

    Examples
    --------
    >>> curve = MrtdCurve(frequency=(500.0, 1000.0, 1500.0), mrtd=(0.05, 0.1, 0.4))
    >>> [round(float(m), 6) for m in mrtd([250.0, 500.0, 1250.0, 1500.0], curve)]
    [0.025, 0.05, 0.2, 0.4]
    >>> float(mrtd(1600.0, curve))
    inf
    """
    curve = _check_curve(curve)
    xp, (f,) = _arrays.arrays(frequency)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    return _arrays.result(_mrtd_law(f, curve, xp))


def resolved_frequency(apparent_delta_t: Array, curve: MrtdCurve) -> Any:
    """The bar frequency resolved at a given temperature difference: the inverse of :func:`mrtd`.

    ``f*`` is the largest frequency with ``MRTD(f*) = ΔT`` under the law of :func:`mrtd`
    (exactly, not by iteration): ``f_1 · ΔT / M_1`` below the first tabulated MRTD, the
    logarithmic interpolation inverted between points, and the cut-off ``f_n`` from the last
    tabulated MRTD up (at +inf too). ``ΔT <= 0`` gives 0. Where the curve is flat the largest
    frequency of the flat part is returned.

    Parameters
    ----------
    apparent_delta_t : array_like
        Temperature difference the target presents at the aperture [K] (after the
        atmosphere: ``τ(R) · ΔT``).
    curve : MrtdCurve
        The sensor's curve.

    Returns
    -------
    array_like
        ``f*`` [cycles/rad] in ``[0, cut-off]``; NaN where the input is NaN.

    Examples
    --------
    >>> curve = MrtdCurve(frequency=(500.0, 1000.0, 1500.0), mrtd=(0.05, 0.1, 0.4))
    >>> [round(float(f), 6) for f in resolved_frequency([0.0, 0.025, 0.2, 0.4, 2.0], curve)]
    [0.0, 250.0, 1250.0, 1500.0, 1500.0]
    """
    curve = _check_curve(curve)
    xp, (dt,) = _arrays.arrays(apparent_delta_t)
    return _arrays.result(_frequency_law(dt, curve, xp))


def mrtd_cycles(
    range: Array,
    critical_dimension: Array,
    delta_t: Array,
    transmittance: Array,
    curve: MrtdCurve,
) -> Any:
    """Resolved cycles across the target for an MRTD-limited thermal imager.

    ``N(R) = f*(τ(R) · |ΔT|) · Dc / R``: the target is resolved to the bar frequency ``f*`` at
    which its apparent temperature difference equals the MRTD (:func:`resolved_frequency`), and
    the critical dimension subtends ``Dc / R`` radians (small angle), so it spans ``f* · Dc / R``
    cycles. This is the STANAG 4347 / NVL static-performance construction (Ratches 1976, see the
    module docstring): the cycles then enter the same transforms as the geometric ones.

    The bench MRTD is the mean of the positive and negative contrast thresholds, so a target
    colder than its background (ΔT < 0) is resolved as a warm one of the same ``|ΔT|``.

    Properties (for range solvers): ``N`` is continuous in every input (if the curve has a
    flat part, ``f*`` jumps across it: the largest frequency is taken); it is
    non-decreasing in ``|ΔT|`` and in ``τ``; with a transmittance that does not increase with
    range (``exp(−γR)``, any path with non-negative extinction) it is strictly decreasing in
    range wherever it is positive, so ``N(R) = N50`` has exactly one root. Out to the range at
    which ``τ(R)|ΔT|`` falls to the curve's last MRTD, ``f*`` is the cut-off and ``N`` is the
    geometric ``f_cut · Dc / R``; beyond it the temperature difference limits.

    Parameters
    ----------
    range : array_like
        Slant range R [m], > 0.
    critical_dimension : array_like
        Critical dimension of the target as seen, Dc [m], > 0.
    delta_t : array_like
        Target–background temperature difference at the target [K] (its magnitude is used).
    transmittance : array_like
        Atmospheric transmittance of the path, τ(R) in [0, 1] (e.g.
        :func:`targetacq.physics.atmosphere.transmittance`).
    curve : MrtdCurve
        The sensor's MRTD curve.

    Returns
    -------
    array_like
        N [cycles], broadcast over the inputs; NaN where any input is NaN.

    Examples
    --------
    >>> curve = MrtdCurve(frequency=(500.0, 1000.0, 1500.0), mrtd=(0.05, 0.1, 0.4))
    >>> round(float(mrtd_cycles(1000.0, 2.3, 2.0, 0.1, curve)), 6)  # τΔT = 0.2 K -> 1250
    2.875
    >>> round(float(mrtd_cycles(1000.0, 2.3, 2.0, 1.0, curve)), 6)  # the cut-off, 1500
    3.45
    """
    curve = _check_curve(curve)
    xp, (r, d, dt, tau) = _arrays.arrays(range, critical_dimension, delta_t, transmittance)
    _arrays.require_positive_or_nan("range", r, xp, "m")
    _arrays.require_positive_or_nan("critical_dimension", d, xp, "m")
    _unit_interval("transmittance", tau, xp)
    f_star = _frequency_law(tau * xp.abs(dt), curve, xp)
    return _arrays.result(f_star * d / r)


# --------------------------------------------------------------------------------------------
# The parametric MRTD and its MTFs.


def system_mtf(
    frequency: Array, *, ifov: Array, aperture: Array, wavelength: Array, blur_sigma: Array = 0.0
) -> Any:
    """System MTF of the MRTD formula: the product of :func:`diffraction_mtf`,
    :func:`detector_mtf` and :func:`blur_mtf` (the MTFs of cascaded linear stages multiply; the
    general product of named components is :func:`targetacq.physics.mtf.system_mtf`).

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    ifov : array_like
        Detector angular subtense [rad], > 0.
    aperture, wavelength : array_like
        D and λ [m], > 0.
    blur_sigma : array_like
        Gaussian blur σ [rad], >= 0 (default 0).

    Returns
    -------
    array_like
        MTF in [0, 1].

    Examples
    --------
    >>> round(float(system_mtf(1000.0, ifov=3.4e-4, aperture=0.05, wavelength=10e-6)), 6)
    0.61289
    """
    xp, (f, i, d, lam, s) = _arrays.arrays(frequency, ifov, aperture, wavelength, blur_sigma)
    _check_mtf_inputs(f, i, d, lam, s, xp)
    return _arrays.result(_system_mtf(f, i, d, lam, s, xp))


def _check_mtf_inputs(f: Array, i: Array, d: Array, lam: Array, s: Array, xp: Any) -> None:
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_positive_or_nan("ifov", i, xp, "rad")
    _arrays.require_positive_or_nan("aperture", d, xp, "m")
    _arrays.require_positive_or_nan("wavelength", lam, xp, "m")
    _arrays.require_nonnegative_or_nan("blur_sigma", s, xp, "rad")


def _system_mtf(f: Array, i: Array, d: Array, lam: Array, s: Array, xp: Any) -> Array:
    return diffraction_mtf(f, lam, d) * detector_mtf(f, i) * blur_mtf(f, s)


def parametric_mrtd(
    frequency: Array,
    *,
    netd: Array,
    ifov: Array,
    aperture: Array,
    wavelength: Array,
    blur_sigma: Array = 0.0,
    frame_rate: Array = DEFAULT_FRAME_RATE,
    eye_integration_time: Array = DEFAULT_EYE_INTEGRATION_TIME,
    snr_threshold: Array = DEFAULT_SNR_THRESHOLD,
    noise_bandwidth_dwell: Array = DEFAULT_NOISE_BANDWIDTH_DWELL,
) -> Any:
    """MRTD of a staring thermal imager from its NETD, system MTF and the observer's integration.

    The four-bar MRTD formula of the NVL static performance model (J. M. Lloyd, *Thermal
    Imaging Systems*, Plenum 1975, its MRTD derivation; J. A. Ratches, Opt. Eng. 15(6) (1976)
    525), for a white-noise detector (its noise filter factor 1):

        MRTD(f) = (π² / (4√14)) · SNR_th · NETD · f / MTF_sys(f)
                  · sqrt( α β / (t_e · F_R · Δf_R τ_d) )

    with ``α = β = IFOV`` (square pixels) and ``MTF_sys`` = :func:`system_mtf`. The printed
    equation numbers were not available when this was written; every factor follows from the
    model's assumptions, so each can be checked: a bar target of frequency ``f`` has bars
    ``W = 1/(2f)`` wide and ``7W`` long (7:1); its fundamental has amplitude ``(4/π) ΔT MTF``,
    which the observer averages over a bar, ``(2/π)`` of it, so the signal is
    ``(8/π²) ΔT MTF``; the white noise of NETD (quoted in the reference bandwidth ``Δf_R``)
    averaged over a dwell ``τ_d`` has variance ``NETD² / (2 Δf_R τ_d)``, and it is averaged
    further over the bar's ``7W²/(αβ)`` pixels and over ``t_e F_R`` frames; setting signal over
    noise to ``SNR_th`` gives the formula, the constant being ``(π²/8) · 2 / sqrt(2 · 7)``.
    For a staring array the dwell is the integration time and the NETD's bandwidth
    ``1/(2 τ_d)``, so ``Δf_R τ_d = 1/2`` (the default).

    The formula ignores sampling (aliasing), display and eye MTFs: bench curves of staring
    arrays stop near the Nyquist frequency ``1/(2 IFOV)``, which this formula does not know;
    sample it below that (:meth:`MrtdCurve.from_parametric`). At and beyond the first zero of
    the system MTF, ``min(1/IFOV, D/λ)``, the result is +inf.

    Parameters
    ----------
    frequency : array_like
        Bar spatial frequency f [cycles/rad], >= 0.
    netd : array_like
        Noise-equivalent temperature difference [K], > 0.
    ifov : array_like
        Detector angular subtense α = β [rad], > 0 (pitch / focal length).
    aperture : array_like
        Entrance-pupil diameter D [m], > 0.
    wavelength : array_like
        Wavelength λ for the diffraction MTF [m], > 0 (the band centre).
    blur_sigma : array_like
        Gaussian optics blur σ [rad], >= 0; default 0.
    frame_rate : array_like
        F_R [Hz], > 0; default 30 Hz.
    eye_integration_time : array_like
        t_e [s], > 0; default 0.1 s.
    snr_threshold : array_like
        SNR_th [-], > 0; default 2.5.
    noise_bandwidth_dwell : array_like
        Δf_R τ_d [-], > 0; default 0.5 (staring array, see above).

    Returns
    -------
    array_like
        MRTD [K]; 0 at f = 0; +inf from the first MTF zero up.

    Examples
    --------
    A 640 × 512, 17 µm camera behind a 50 mm f/1.0 lens (IFOV 0.34 mrad), NETD 50 mK, 10 µm:

    >>> round(float(parametric_mrtd(
    ...     1000.0, netd=0.05, ifov=17e-6 / 0.05, aperture=0.05, wavelength=10e-6)), 5)
    0.03734
    """
    xp, (f, n, i, d, lam, s, fr, te, k, bd) = _arrays.arrays(
        frequency,
        netd,
        ifov,
        aperture,
        wavelength,
        blur_sigma,
        frame_rate,
        eye_integration_time,
        snr_threshold,
        noise_bandwidth_dwell,
    )
    _check_mtf_inputs(f, i, d, lam, s, xp)
    _arrays.require_positive_or_nan("netd", n, xp, "K")
    _arrays.require_positive_or_nan("frame_rate", fr, xp, "Hz")
    _arrays.require_positive_or_nan("eye_integration_time", te, xp, "s")
    _arrays.require_positive_or_nan("snr_threshold", k, xp)
    _arrays.require_positive_or_nan("noise_bandwidth_dwell", bd, xp)
    mtf = _system_mtf(f, i, d, lam, s, xp)
    # Beyond the first zero of the MTF (detector: 1/IFOV; optics: D/λ) the formula is void.
    first_zero = xp.minimum(1.0 / i, d / lam)
    valid = (f < first_zero) & (mtf > 0)
    safe = xp.where(valid, mtf, 1.0)
    value = MRTD_CONSTANT * k * n * f / safe * xp.sqrt(i * i / (te * fr * bd))
    out = xp.where(valid, value, xp.inf)
    missing = xp.isnan(f + n + i + d + lam + s + fr + te + k + bd)
    return _arrays.result(xp.where(missing, xp.nan, out))
