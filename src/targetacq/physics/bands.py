"""Named spectral bands (Tables 6.1 and 7.1 of Sonesson 2004) and band validation."""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from targetacq.base.tables import load_table

__all__ = ["BANDS", "band_limits", "band_name", "parse_band"]


@functools.cache
def _bands() -> Mapping[str, tuple[float, float]]:
    table = load_table("bands")
    return MappingProxyType(
        {
            name: (low * 1e-6, high * 1e-6)
            for name, low, high in zip(
                table.column("band"),
                table.numbers("low_um"),
                table.numbers("high_um"),
                strict=True,
            )
        }
    )


BANDS: Mapping[str, tuple[float, float]] = _bands()
"""Named bands → (λ1, λ2) [m]: visible 0.4–0.7 µm, mwir 3–5 µm, lwir 8–12 µm."""


def band_limits(band: Any) -> tuple[float, float]:
    """(λ1, λ2) [m] of a band given by name or as a pair of wavelengths in metres.

    Raises
    ------
    ValueError
        Unknown name (the valid ones are listed), or not ``0 <= λ1 < λ2`` (λ2 may be +inf: the
        whole spectrum).

    Examples
    --------
    >>> from targetacq.physics.bands import band_limits
    >>> [round(x * 1e6, 6) for x in band_limits("lwir")]
    [8.0, 12.0]
    """
    if isinstance(band, str):
        if band not in BANDS:
            raise ValueError(f"unknown band {band!r}; named bands: {', '.join(BANDS)}")
        return BANDS[band]
    try:
        low, high = (float(v) for v in band)
    except (TypeError, ValueError) as error:
        raise ValueError(
            f"band must be a name ({', '.join(BANDS)}) or a pair (λ1, λ2) in metres; got {band!r}"
        ) from error
    if math.isnan(low) or math.isnan(high) or not 0 <= low < high:
        raise ValueError(f"band must satisfy 0 <= λ1 < λ2 [m]; got ({low:g}, {high:g})")
    return low, high


def parse_band(text: str, name: str = "band") -> tuple[float, float]:
    """(λ1, λ2) [m] from a band's name or text like "8-12um" or "8-12 um" (CLI, scenarios).

    Raises
    ------
    ValueError
        Naming the input (``name``), the named bands and the form expected.

    Examples
    --------
    >>> from targetacq.physics.bands import parse_band
    >>> [round(x * 1e6, 6) for x in parse_band("3-5 um")]
    [3.0, 5.0]
    """
    from targetacq.base.units import parse_quantity

    if text in BANDS:
        return BANDS[text]
    match = re.fullmatch(r"\s*([\d.]+)\s*-\s*([\d.]+)\s*([A-Za-zµ]+)\s*", text)
    if match is None:
        raise ValueError(f"{name} must be one of {', '.join(BANDS)} or like 8-12um; got {text!r}")
    low, high, unit = match.groups()
    limits = (
        parse_quantity(f"{low} {unit}", "length", name),
        parse_quantity(f"{high} {unit}", "length", name),
    )
    if not 0 <= limits[0] < limits[1]:  # finite already
        raise ValueError(f"{name} must satisfy 0 <= λ1 < λ2 (e.g. 8-12um); got {text!r}")
    return band_limits(limits)


def band_name(band: Any) -> str:
    """The name of the Table 6.1 / 7.1 band that a band is or matches exactly.

    Raises
    ------
    ValueError
        If the band is not one of the named bands (tables are given for those only).

    Examples
    --------
    >>> from targetacq.physics.bands import band_name
    >>> band_name((8e-6, 12e-6))
    'lwir'
    """
    limits = band_limits(band)
    for name, named in BANDS.items():
        if all(math.isclose(a, b, rel_tol=1e-9) for a, b in zip(limits, named, strict=True)):
            return name
    raise ValueError(
        f"the tables are given for the bands {', '.join(BANDS)} only; got {limits[0] * 1e6:g}-"
        f"{limits[1] * 1e6:g} um"
    )
