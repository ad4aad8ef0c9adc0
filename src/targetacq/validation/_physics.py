"""Sections of chapters 5–7 of Sonesson (2004): materials, atmosphere, radiometry, optics.

Published values come from the bundled tables (Tables 6.1, 7.1) or, for the few numbers the
thesis prints in its text, from that text (quoted in each check). The Planck checks have no
printed value: their reference is a numerical quadrature of Planck's law (6.2) done here, with
SciPy's CODATA constants, independently of the closed-form series the package uses.
"""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np
import scipy.constants as codata
from matplotlib.figure import Figure
from scipy import integrate

from targetacq.base.tables import load_table
from targetacq.physics import atmosphere, optics, radiometry
from targetacq.physics.bands import BANDS
from targetacq.validation._model import Check, Section, as_float, half_unit, new_figure

__all__ = [
    "extinction_section",
    "materials_section",
    "optics_section",
    "planck_exitance",
    "planck_section",
    "terms_section",
]

_BAND_TEXT = {"visible": "0.4–0.7 µm", "mwir": "3–5 µm", "lwir": "8–12 µm"}
_QUADRATURE_RTOL = 1e-12
_PLANCK_TOLERANCE = 1e-9  # relative: the quadrature is good to ~1e-12


def _band_of(text: str) -> str:
    return f"{text} ({_BAND_TEXT[text]})"


# --------------------------------------------------------------------------------------------
# Table 6.1
# --------------------------------------------------------------------------------------------


def materials_section() -> Section:
    """Table 6.1: emissivity ``1 − r`` of the materials at the printed reflectances."""
    table = load_table("reflectance")
    checks = []
    for material, band, low, high in table.rows:
        for bound, printed in (("low", low), ("high", high)):
            item = f"{material}, {_band_of(band)}, {bound} reflectance ({printed or '–'} %)"
            if not printed.strip():
                try:
                    model: float | str = radiometry.material_emissivity(material, band, bound)
                except ValueError:
                    model = "–"
                checks.append(Check(item, "–", model, printed="–", note="not given in Table 6.1"))
                continue
            checks.append(
                Check(
                    item,
                    1.0 - float(printed) / 100.0,
                    radiometry.material_emissivity(material, band, bound),
                    half_unit(printed) / 100.0,
                    "",
                    f"1 − {printed} %",
                )
            )
    return Section(
        key="table-6-1",
        title="Table 6.1: reflectance → emissivity of materials",
        source="Sonesson (2004) Table 6.1 (p. 35), reflectance in % (Hudson, via [17]); "
        "emissivity of an opaque body ε = 1 − r, Eq. (6.5) with Kirchhoff's law.",
        method="targetacq.physics.radiometry.material_emissivity(material, band, bound), bound "
        "'low' or "
        "'high' reflectance (the low reflectance gives the high emissivity).",
        checks=tuple(checks),
        notes="Published column: 1 − the printed reflectance; its tolerance is the printed "
        "reflectance's (±0.5 %, i.e. ±0.005 in emissivity). The thesis gives no visible "
        "reflectance for ice: the package refuses that cell rather than invent one.",
        provenance=table.provenance,
        figure=_materials_figure,
    )


def _materials_figure() -> Figure:
    table = load_table("reflectance")
    labels, lows, highs, model_lows, model_highs = [], [], [], [], []
    for material, band, low, high in table.rows:
        if not low.strip():
            continue
        labels.append(f"{material}, {_BAND_TEXT[band]}")
        lows.append(1.0 - float(high) / 100.0)
        highs.append(1.0 - float(low) / 100.0)
        model_lows.append(radiometry.material_emissivity(material, band, "high"))
        model_highs.append(radiometry.material_emissivity(material, band, "low"))
    return _range_bars(
        labels,
        lows,
        highs,
        model_lows,
        model_highs,
        "emissivity ε = 1 − r",
        "Table 6.1: printed ranges (bars) and the package's ends (markers)",
        log=False,
    )


def _range_bars(
    labels: list[str],
    lows: list[float],
    highs: list[float],
    model_lows: list[float],
    model_highs: list[float],
    xlabel: str,
    title: str,
    log: bool,
) -> Figure:
    fig, ax = new_figure(8.0, 0.24 * len(labels) + 1.4, left=1.6)
    y = np.arange(len(labels))
    widths = np.array(highs) - np.array(lows)
    ax.barh(y, widths, left=lows, height=0.6, color="#aec7e8", label="printed range")
    ax.plot(model_lows, y, "|", color="#d62728", ms=12, mew=2, label="model, low end")
    ax.plot(model_highs, y, "|", color="#1f77b4", ms=12, mew=2, label="model, high end")
    ax.set_yticks(y, labels, fontsize=7)
    ax.invert_yaxis()
    if log:
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.grid(True, axis="x", which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(title)
    return fig


# --------------------------------------------------------------------------------------------
# Tables 7.1 and 7.2
# --------------------------------------------------------------------------------------------


def extinction_section() -> Section:
    """Table 7.1: the extinction coefficients of the obscurants, cell by cell."""
    table = load_table("extinction")
    checks = []
    for obscurant, band, low, high in table.rows:
        for level, printed in (("low", low), ("high", high)):
            model = atmosphere.obscurant_extinction(obscurant, band, level) * 1e3
            note = "printed '≈ 0.02' (one value)" if low == high else ""
            checks.append(
                Check(
                    f"{obscurant}, {_band_of(band)}, {level} end",
                    float(printed),
                    model,
                    half_unit(printed),
                    "Np/km",
                    printed,
                    note,
                )
            )
    return Section(
        key="table-7-1",
        title="Table 7.1: extinction coefficients of the obscurants",
        source="Sonesson (2004) Table 7.1 (p. 42), 'Extinction coefficient of atmospheric "
        "obscurants (low altitude)', Np/km.",
        method="targetacq.physics.atmosphere.obscurant_extinction(obscurant, band, level) × 1000 "
        "(Np/m → Np/km), level 'low' or 'high'.",
        checks=tuple(checks),
        notes="The package's 'nominal' level, the geometric mean of each cell, is its own choice "
        "(the cells span up to two decades) and has no printed counterpart.",
        provenance=table.provenance,
        figure=_extinction_figure,
    )


def _extinction_figure() -> Figure:
    table = load_table("extinction")
    labels = [f"{o}, {_BAND_TEXT[b]}" for o, b, _, _ in table.rows]
    lows = [float(lo) for _, _, lo, _ in table.rows]
    highs = [float(hi) for _, _, _, hi in table.rows]
    # A one-value cell ("≈ 0.02") gets a visible sliver.
    highs = [max(hi, lo * 1.05) for lo, hi in zip(lows, highs, strict=True)]
    model_lows = [atmosphere.obscurant_extinction(o, b, "low") * 1e3 for o, b, _, _ in table.rows]
    model_highs = [atmosphere.obscurant_extinction(o, b, "high") * 1e3 for o, b, _, _ in table.rows]
    return _range_bars(
        labels,
        lows,
        highs,
        model_lows,
        model_highs,
        "extinction coefficient γ [Np/km]",
        "Table 7.1: printed ranges (bars) and the package's ends (markers)",
        log=True,
    )


# Table 7.2 as printed (p. 42): extinction interval [Np/km], descriptive term, visual range.
_TABLE_7_2 = (
    ("< 0.1", "Very low", "> 30 km, very clear"),
    ("0.1 - 0.5", "Low", "6 - 30 km, clear to hazy"),
    ("0.5 - 2", "Medium", "2 - 6 km, hazy"),
    ("> 2", "High", "< 2km, foggy"),
)
# Extinctions [Np/km] inside each printed interval, away from the shared ends.
_TERM_POINTS = ((0.0, 0.05, 0.099), (0.101, 0.3, 0.499), (0.501, 1.0, 1.999), (2.001, 5.0, 20.0))


def terms_section() -> Section:
    """Table 7.2: the descriptive term and visual range of an extinction coefficient."""
    checks = []
    for (interval, term, visual), points in zip(_TABLE_7_2, _TERM_POINTS, strict=True):
        for gamma in points:
            found_term, found_visual = atmosphere.extinction_term(gamma / 1e3)
            checks.append(
                Check(
                    f"γ = {gamma:g} Np/km (printed interval {interval})",
                    f"{term}; {visual}",
                    f"{found_term}; {found_visual}",
                    printed=f"{term}; {visual}",
                )
            )
    return Section(
        key="table-7-2",
        title="Table 7.2: descriptive terms of the extinction",
        source="Sonesson (2004) Table 7.2 (p. 42), 'Explanations to Table 7.1'.",
        method="targetacq.physics.atmosphere.extinction_term(γ / 1000) (Np/km → Np/m).",
        checks=tuple(checks),
        notes="Text compared without case and white space. The printed intervals share their "
        "ends (0.1, 0.5, 2 Np/km belong to two rows each); the package puts an end in the upper "
        "row, so the points checked here lie inside the intervals.",
        provenance=load_table("extinction_terms").provenance,
    )


# --------------------------------------------------------------------------------------------
# Planck
# --------------------------------------------------------------------------------------------


def _planck(wavelength: float, temperature: float) -> float:
    """Planck's spectral exitance (6.2) [W m⁻² m⁻¹], with SciPy's CODATA constants."""
    x = codata.h * codata.c / (wavelength * codata.k * temperature)
    if x > 700.0:
        return 0.0
    return 2.0 * math.pi * codata.h * codata.c**2 / wavelength**5 / math.expm1(x)


def planck_exitance(temperature: float, low: float, high: float) -> float:
    """Band exitance by adaptive quadrature of Planck's law, the reference of the Planck checks.

    Parameters
    ----------
    temperature : float
        T [K], > 0.
    low, high : float
        Band limits λ1 < λ2 [m]; ``high`` may be ``inf`` and ``low`` 0.

    Returns
    -------
    float
        ∫ M_λ dλ over [λ1, λ2] [W/m²], relative accuracy about 1e-12 (SciPy ``quad``, the
        interval split at multiples of the peak wavelength so that no piece is mostly empty).
    """
    peak = codata.Wien / temperature
    cuts = [low, *(k * peak for k in (0.25, 1.0, 4.0, 16.0) if low < k * peak < high), high]
    total = 0.0
    for a, b in itertools.pairwise(cuts):
        value, _ = integrate.quad(
            _planck, a, b, args=(temperature,), epsabs=0.0, epsrel=_QUADRATURE_RTOL, limit=400
        )
        total += value
    return total


_PLANCK_CASES = (
    ("lwir", 250.0),
    ("lwir", 270.0),
    ("lwir", 300.0),
    ("lwir", 330.0),
    ("lwir", 1500.0),
    ("mwir", 270.0),
    ("mwir", 300.0),
    ("mwir", 330.0),
    ("mwir", 1000.0),
    ("visible", 5800.0),
)


def planck_section() -> Section:
    """Band exitance (6.12) against quadrature, and σT⁴ (6.1)."""
    checks = []
    for band, t in _PLANCK_CASES:
        low, high = BANDS[band]
        reference = planck_exitance(t, low, high)
        checks.append(
            Check(
                f"{_band_of(band)} at {t:g} K",
                reference,
                as_float(radiometry.band_exitance(t, band)),
                _PLANCK_TOLERANCE * reference,
                "W/m²",
                f"{reference:.10g}",
                "reference: quadrature of (6.2)",
            )
        )
    t = 300.0
    sigma_t4 = codata.Stefan_Boltzmann * t**4
    checks.append(
        Check(
            "all wavelengths at 300 K: band exitance over (0, ∞) vs σT⁴",
            sigma_t4,
            as_float(radiometry.band_exitance(t, (0.0, math.inf))),
            _PLANCK_TOLERANCE * sigma_t4,
            "W/m²",
            f"{sigma_t4:.10g}",
            "reference: σT⁴ with CODATA σ",
        )
    )
    total = planck_exitance(t, 0.0, math.inf)
    checks.append(
        Check(
            "all wavelengths at 300 K: σT⁴ (6.1) vs quadrature of (6.2)",
            total,
            as_float(radiometry.stefan_boltzmann_exitance(t)),
            _PLANCK_TOLERANCE * total,
            "W/m²",
            f"{total:.10g}",
            "reference: quadrature of (6.2) over (0, ∞)",
        )
    )
    return Section(
        key="planck",
        title="Planck's law: band exitance (6.12) and Stefan–Boltzmann (6.1)",
        source="Sonesson (2004) Eqs. (6.1), (6.2), (6.12), with 2πhc² (the thesis prints 2πhc in "
        "(6.12), a misprint: the units need c²). No values are printed: the reference is a "
        "numerical quadrature of (6.2) made by this page (SciPy quad, CODATA constants from "
        "scipy.constants).",
        method="targetacq.physics.radiometry.band_exitance(T, band) (closed-form series, no "
        "quadrature) "
        "and targetacq.physics.radiometry.stefan_boltzmann_exitance(T).",
        checks=tuple(checks),
        notes="Tolerance: 1e-9 relative, a thousand times the quadrature's accuracy. The "
        "temperatures cover both branches of the package's series (c2/(λT) above and below 2: "
        "8–12 µm at 1500 K is below).",
        figure=_planck_figure,
    )


def _planck_figure() -> Figure:
    temperatures = np.linspace(200.0, 400.0, 201)
    fig, ax = new_figure(8.0, 4.2)
    for band, colour in (("lwir", "#d62728"), ("mwir", "#1f77b4")):
        ax.plot(
            temperatures,
            radiometry.band_exitance(temperatures, band),
            color=colour,
            lw=2,
            label=f"model, {_band_of(band)}",
        )
        points = [t for b, t in _PLANCK_CASES if b == band and t <= 400]
        low, high = BANDS[band]
        ax.plot(
            points,
            [planck_exitance(t, low, high) for t in points],
            "o",
            color=colour,
            mec="black",
            ms=7,
        )
    ax.plot([], [], "o", color="0.6", mec="black", label="quadrature of (6.2)")
    ax.set_yscale("log")
    ax.set_xlabel("temperature T [K]")
    ax.set_ylabel("band exitance M [W/m²]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("Band exitance: the package's closed form and quadrature")
    return fig


# --------------------------------------------------------------------------------------------
# Check values in the text: optics, vignetting, units, SNR
# --------------------------------------------------------------------------------------------


def optics_section() -> Section:
    """The numbers the thesis prints in its text: diffraction, cycles, cos⁴, Np ↔ dB, SNR."""
    angle = as_float(optics.diffraction_angle(10e-6, 0.122))
    ifov = 1e-4
    checks = [
        Check(
            "Eq. (5.3), D = 122 mm, λ = 10 µm: smallest resolvable angle",
            1.0e-4,
            angle,
            half_unit("1.0e-4"),
            "rad",
            "0.1 m at 1000 m",
            "§5.5: 'with a lens diameter of 122 mm and a wavelength of 10 µm, details larger "
            "than 0.1 m can be seen on an object 1000 m away'",
        ),
        Check(
            "Eq. (5.3): the same as a detail at 1000 m",
            0.1,
            1000.0 * math.tan(angle),
            half_unit("0.1"),
            "m",
            "0.1",
        ),
        Check(
            "Fig. 3.3: a target 2.5 pixel rows high",
            1.25,
            as_float(optics.cycles_on_target(2.5 * ifov * 1000.0, 1000.0, ifov)),
            half_unit("1.25"),
            "cycles",
            "1.25 LP/TGT",
            "one cycle (line pair) is two pixel rows",
        ),
        Check(
            "Eq. (6.17), vignetting cos⁴θ at θ = 30°",
            0.5625,
            as_float(radiometry.irradiance_at_sensor(1.0, 1.0, off_axis_angle=math.radians(30))),
            half_unit("0.5625"),
            "",
            "'almost half' (cos⁴ 30° = 9/16)",
            "§6.6",
        ),
        Check(
            "Eq. (6.17), vignetting cos⁴θ at θ = 10°",
            0.94,
            as_float(radiometry.irradiance_at_sensor(1.0, 1.0, off_axis_angle=math.radians(10))),
            half_unit("0.94"),
            "",
            "94 %",
            "§6.6: 'at 10° 94 % remains'",
        ),
        Check(
            "§7.4: 1 dB/km in Np/km",
            0.23,
            as_float(atmosphere.db_per_km_to_np_per_km(1.0)),
            half_unit("0.23"),
            "Np/km",
            "0.23",
            "printed 'Np/km = 0.23 dB/km', the wrong way round: 0.23 converts dB/km to Np/km "
            "(1 dB/km = 0.2303 Np/km)",
        ),
        Check(
            "1 Np/km in dB/km (10·log10 e, the neper and the decibel of power)",
            4.343,
            as_float(atmosphere.np_per_km_to_db_per_km(1.0)),
            half_unit("4.343"),
            "dB/km",
            "4.343",
            "definition (ISO 80000-3), not printed in the thesis",
        ),
        Check(
            "Eqs. (7.5)–(7.7): SNR at τ = 0.5",
            0.0,
            as_float(atmosphere.snr_from_transmittance(0.5)),
            1e-12,
            "dB",
            "SNR = 0",
            "§7.4: 'half the original signal … τ = 0.5 (SNR = 0)'",
        ),
        Check(
            "Eqs. (7.5)–(7.7): SNR at τ = 1 (perfectly clear)",
            math.inf,
            as_float(atmosphere.snr_from_transmittance(1.0)),
            0.0,
            "dB",
            "SNR = ∞",
        ),
        Check(
            "Eqs. (7.5)–(7.7): SNR at τ = 0 (perfect fog)",
            -math.inf,
            as_float(atmosphere.snr_from_transmittance(0.0)),
            0.0,
            "dB",
            "SNR = −∞",
        ),
    ]
    return Section(
        key="text",
        title="Check values in the text: diffraction, cycles, vignetting, Np ↔ dB, SNR",
        source="Sonesson (2004) §5.5 (Eq. (5.3)), Fig. 3.3, §6.6 (Eq. (6.17)), §7.4 "
        "(Eqs. (7.5)–(7.7)).",
        method="targetacq.physics.optics.diffraction_angle, "
        "targetacq.physics.optics.cycles_on_target, "
        "targetacq.physics.radiometry.irradiance_at_sensor (lens, unit intensity and range), "
        "targetacq.physics.atmosphere.db_per_km_to_np_per_km / np_per_km_to_db_per_km, "
        "targetacq.physics.atmosphere.snr_from_transmittance.",
        checks=tuple(checks),
        notes="Eq. (5.3) is sin Δθ = 1.22 λ/D: 1.22 × 10 µm / 122 mm = 1e-4 exactly, and the "
        "arcsine adds 1.7e-13 rad.",
        figure=_vignetting_figure,
    )


def _vignetting_figure() -> Figure:
    degrees = np.linspace(0.0, 60.0, 241)
    fig, ax = new_figure(6.0, 3.6)
    factor: Any = radiometry.irradiance_at_sensor(1.0, 1.0, off_axis_angle=np.radians(degrees))
    ax.plot(degrees, factor, color="#1f77b4", lw=2, label="model, cos⁴θ (6.17)")
    ax.plot([30.0, 10.0], [0.5625, 0.94], "o", color="#d62728", mec="black", label="§6.6")
    ax.set_xlabel("off-axis angle θ [°]")
    ax.set_ylabel("relative irradiance")
    ax.set_ylim(0, 1.05)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Vignetting: 30° → 0.5625, 10° → 94 %")
    return fig
