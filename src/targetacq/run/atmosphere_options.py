"""Options of a named atmosphere (``--atmosphere``, ``--aerosol``, ``--visibility``,
``--altitude``) for every front end: text with units in, a checked
:class:`targetacq.physics.named_atmospheres.NamedPath` and its description out.

The physics is in :mod:`targetacq.physics.named_atmospheres`; this only reads the options.
"""

from __future__ import annotations

from typing import Any

from targetacq.base.tables import load_table
from targetacq.base.units import parse_quantity
from targetacq.physics.named_atmospheres import (
    AEROSOLS,
    ATMOSPHERES,
    NAMED_BANDS,
    NamedPath,
)

__all__ = ["NAMED_PATH_OPTIONS", "named_path_description", "option_named_path"]

NAMED_PATH_OPTIONS = ("atmosphere", "aerosol", "visibility", "path_altitude")
"""The options of a named atmosphere, by keyword name."""


def option_named_path(
    atmosphere: str | None,
    aerosol: str | None,
    visibility: str | None = None,
    path_altitude: str | None = None,
) -> NamedPath | None:
    """The named path of the options (None where neither ``--atmosphere`` nor ``--aerosol`` is
    given): the atmosphere defaults to us-standard, the aerosol to rural, the visibility to the
    aerosol's default, the altitude to sea level.

    Raises
    ------
    ValueError
        Naming the option and its valid choices or range.

    Examples
    --------
    >>> from targetacq.run.atmosphere_options import option_named_path
    >>> option_named_path("tropical", "rural", "23km")
    NamedPath(atmosphere='tropical', aerosol='rural', visibility=23000.0, altitude=0.0)
    """
    if atmosphere is None and aerosol is None:
        if path_altitude is not None:
            raise ValueError(
                "--path-altitude goes with --atmosphere or --aerosol (a named atmosphere)"
            )
        return None
    for option, value, choices in (
        ("--atmosphere", atmosphere, ATMOSPHERES),
        ("--aerosol", aerosol, AEROSOLS),
    ):
        if value is not None and value not in choices:
            raise ValueError(f"{option} must be one of {', '.join(choices)}; got {value!r}")
    vis = None if visibility is None else parse_quantity(visibility, "length", "--visibility")
    height = (
        0.0 if path_altitude is None else parse_quantity(path_altitude, "length", "--path-altitude")
    )
    try:
        return NamedPath(atmosphere or "us-standard", aerosol or "rural", vis, height)
    except ValueError as error:
        text = str(error)
        text = text.replace("altitude must", "--path-altitude must", 1)
        raise ValueError(text if text.startswith("--") else f"--{text}") from error


def named_path_description(path: NamedPath, band: Any) -> dict[str, Any]:
    """The named path as a report states it: model, settings [SI] and the table's source."""
    vis = path.meteorological_range
    band_text = next(
        (n for n, lim in NAMED_BANDS.items() if lim == band or n == band),
        f"{band[0] * 1e6:g}-{band[1] * 1e6:g} um" if not isinstance(band, str) else band,
    )
    return {
        "model": "named",
        "atmosphere": path.atmosphere,
        "aerosol": path.aerosol,
        "visibility_m": vis,
        "altitude_m": path.altitude,
        "band": band_text,
        "description": f"{path.atmosphere} atmosphere, {path.aerosol} aerosol"
        + ("" if vis is None else f", visibility {vis / 1e3:g} km")
        + f", horizontal path at {path.altitude:g} m",
        "source": "LOWTRAN7 (Kneizys et al. 1988) horizontal paths, "
        f"{load_table('named_atmospheres').provenance.splitlines()[2].split(' (')[0].strip()}, "
        "tabulated in data/named_atmospheres.csv",
    }
