"""Validation: every published value the model reproduces, with the model's value and residual.

The page a sceptical colleague is sent: for each table of Sonesson (2004), *A Probabilistic
Approach to Conceptual Sensor Modeling* (LiTH-ISY-EX-3428, Linköping), that the package
implements, the printed values next to what the package computes, the residuals, and a figure of
the model's curve through the printed points. The sections, in page order:

- Tables 3.1 and 3.2: the criteria registry's N50s; every transform gives P = 0.5 at N50;
- Table 3.3: C2NVEO at the printed cycles, optimistic and pessimistic ends;
- Table 3.5: Schmieder–Weathersby at the printed cycles, by clutter region;
- Table 3.4: the observations against the model at their SCR (a *comparison*: the model reads
  the binned Table 3.5, so these residuals are not zero; a transform fitted to Table 3.4, when
  one is registered as ``schmieder-weathersby-observed``, gets its own column);
- Table 6.1: emissivity ``1 − r`` of the materials; Tables 7.1 and 7.2: extinction and its terms;
- Planck: band exitance (6.12) against a numerical quadrature of (6.2) done here, and σT⁴ (6.1);
- the check values in the text: diffraction (5.3), Fig. 3.3's cycles, vignetting cos⁴ (6.17),
  Np/km ↔ dB/km (§7.4), the SNR of (7.5)–(7.7);
- the signature at the sensor: sky reflection (§6.3), Koschmieder's and Duntley–Middleton's
  contrast reduction by airlight, the path's emission (§7.2), the hot spot's 0.5 LP/TGT (§3.9);
- a vendor's published DRI ranges (thermal-camera datasheet pixel rule);
- the TTP metric: the V50s of ``ttp-vehicles``, its TTPF at V50 and the diffraction MTF's closed
  form (the V50s are quoted values; no printed worked example of the TTP chain is reproduced);
- named atmospheres: the LOWTRAN7 band-transmittance table against published MODTRAN spectra
  (midlatitude summer, rural aerosol), within 20 %;
- noise that can hide a target: the ``contrast`` SNR law at Eq. (7.7)'s reference target, the
  detection threshold's reference points, and MRTD-limited ranges against an independent solution.

Published values are read from the bundled tables (``targetacq/data``, with their provenance)
or quoted from the thesis's text; model values come from the public functions. A check's
tolerance is half a unit in the last printed digit (:func:`half_unit`).

Examples
--------
>>> summary = validation_summary()
>>> summary.within == summary.checks
True
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from targetacq.io.files import output_path, write_atomically
from targetacq.validation._dri import vendor_section
from targetacq.validation._model import Check, Section, Summary, half_unit, summarise
from targetacq.validation._named_atmospheres import named_atmospheres_section
from targetacq.validation._noise import noise_section
from targetacq.validation._page import render_page
from targetacq.validation._physics import (
    extinction_section,
    materials_section,
    optics_section,
    planck_exitance,
    planck_section,
    terms_section,
)
from targetacq.validation._signature import signature_section
from targetacq.validation._transforms import (
    OBSERVED_TRANSFORM,
    c2nveo_section,
    johnson_section,
    observed_section,
    schmieder_weathersby_section,
)
from targetacq.validation._ttp import ttp_section

__all__ = [
    "OBSERVED_TRANSFORM",
    "Check",
    "Section",
    "Summary",
    "half_unit",
    "planck_exitance",
    "render_validation",
    "validation_report",
    "validation_sections",
    "validation_summary",
    "validation_tables",
    "write_validation",
]


def validation_sections(transforms: Mapping[str, Any] | None = None) -> tuple[Section, ...]:
    """All sections of the validation page, in page order.

    Parameters
    ----------
    transforms : mapping, optional
        The transforms registry to look for :data:`OBSERVED_TRANSFORM` in (default
        :data:`targetacq.acquisition.transforms.TRANSFORMS`).

    Returns
    -------
    tuple of Section
        Each with its source, its checks (published, model, residual, tolerance) and a figure
        function; figures are drawn only when the page is rendered.
    """
    return (
        johnson_section(),
        c2nveo_section(),
        schmieder_weathersby_section(),
        observed_section(transforms),
        materials_section(),
        extinction_section(),
        terms_section(),
        planck_section(),
        optics_section(),
        signature_section(),
        vendor_section(),
        ttp_section(),
        named_atmospheres_section(),
        noise_section(),
    )


def validation_tables(sections: Sequence[Section] | None = None) -> dict[str, pd.DataFrame]:
    """The comparison tables as data, one DataFrame per section.

    Parameters
    ----------
    sections : sequence of Section, optional
        Default: :func:`validation_sections`.

    Returns
    -------
    dict of str to pandas.DataFrame
        By section key (``"table-3-3"``, ``"planck"``, ...). Columns: ``item``, ``printed`` (as
        in the source), ``published`` and ``model`` (float, or text for categorical values),
        ``residual`` (model − published; NaN for text), ``tolerance`` (absolute), ``unit``,
        ``within`` (bool), ``exact`` (False for comparisons), ``note``, and ``model: NAME`` /
        ``residual: NAME`` for alternative models. ``DataFrame.attrs`` holds ``title``,
        ``source`` and ``method``.
    """
    chosen = validation_sections() if sections is None else sections
    tables = {}
    for section in chosen:
        records = []
        for check in section.checks:
            residual = check.residual
            record: dict[str, Any] = {
                "item": check.item,
                "printed": check.printed,
                "published": check.published,
                "model": check.model,
                "residual": float("nan") if residual is None else residual,
                "tolerance": check.tolerance,
                "unit": check.unit,
                "within": check.within,
                "exact": check.exact,
                "note": check.note,
            }
            for name in section.alternative_names:
                value = check.alternatives.get(name)
                other = check.alternative_residual(name)
                record[f"model: {name}"] = float("nan") if value is None else value
                record[f"residual: {name}"] = float("nan") if other is None else other
            records.append(record)
        frame = pd.DataFrame.from_records(records)
        frame.attrs.update(title=section.title, source=section.source, method=section.method)
        tables[section.key] = frame
    return tables


def validation_summary(sections: Sequence[Section] | None = None) -> Summary:
    """Counts over the sections: checks, how many within tolerance, the worst residual."""
    return summarise(list(validation_sections() if sections is None else sections))


def render_validation(sections: Sequence[Section] | None = None) -> str:
    """The validation page as one self-contained HTML string (figures embedded as PNG)."""
    from targetacq import __version__

    chosen = validation_sections() if sections is None else sections
    return render_page(chosen, version=__version__)


def write_validation(path: str | Path, page: str) -> Path:
    """Write the page atomically (:func:`targetacq.io.files.write_atomically`).

    Raises
    ------
    ValueError
        If the suffix is not .html/.htm, the folder does not exist, or (``OutputError``) the file
        cannot be written: the message names the file and the reason.
    """
    out, _ = output_path(path, ("html", "htm"), "the validation page")
    return write_atomically(out, lambda p: p.write_text(page, encoding="utf-8"))


def validation_report(path: str | Path = "validation.html") -> Path:
    """Compute every check, render the page and write it to ``path`` (.html).

    Parameters
    ----------
    path : str or Path
        Output file; its folder must exist.

    Returns
    -------
    Path
        The file written.
    """
    output_path(path, ("html", "htm"), "the validation page")  # before any work
    return write_validation(path, render_validation())
