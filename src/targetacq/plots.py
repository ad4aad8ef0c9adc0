"""Figures: range-performance curves, the transforms, the atmosphere (matplotlib, headless).

Figures are built with :class:`matplotlib.figure.Figure` directly, never through pyplot, so no
display or global state is involved. :data:`PLOT_KINDS` is the registry of the CLI's
``targetacq plot KIND``. Colours are fixed per task so that a reader can follow a task across
figures; line styles tell cases apart.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from targetacq import atmosphere, transforms
from targetacq.bands import band_limits, band_name
from targetacq.criteria import get_criterion
from targetacq.outputs import output_path, write_atomically

__all__ = [
    "FIGURE_FORMATS",
    "PLOT_KINDS",
    "TASK_COLOURS",
    "plot_atmosphere",
    "plot_range_performance",
    "plot_transforms",
    "save_figure",
]

TASK_COLOURS: Mapping[str, str] = MappingProxyType(
    {"detection": "#1f77b4", "recognition": "#d62728", "identification": "#2ca02c"}
)
"""Colour of each task in every figure."""

REGION_COLOURS: Mapping[str, str] = MappingProxyType(
    {"low": "#17becf", "medium": "#ff7f0e", "high": "#7f3c8d"}
)
_LINESTYLES = ("-", "--", ":", "-.")
FIGURE_FORMATS = ("png", "svg")


def plot_range_performance(
    performance: Any, title: str | None = None, probabilities: Sequence[float] | None = None
) -> Figure:
    """P(detection), P(recognition), P(identification) against range, with DRI ranges marked.

    Parameters
    ----------
    performance : targetacq.ranges.RangePerformance
        From :func:`targetacq.ranges.range_performance`.
    title : str, optional
        The sensor and target, e.g. "640×512 17 µm, f = 75 mm — 2.3 m target".
    probabilities : sequence of float, optional
        Which DRI probabilities to mark (default: all in ``performance.dri``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    curves, dri = performance.curves, performance.dri
    km = curves["range"].values / 1e3
    fig = Figure(figsize=(8.0, 5.0), dpi=100, layout="constrained")
    ax = fig.add_subplot()
    cases = list(curves["case"].values)
    marks = sorted(set(dri["probability"])) if probabilities is None else list(probabilities)
    for k, case in enumerate(cases):
        style = _LINESTYLES[k % len(_LINESTYLES)]
        for task, colour in TASK_COLOURS.items():
            label = task if len(cases) == 1 else f"{task} — {case}"
            ax.plot(km, curves[task].sel(case=case).values, style, color=colour, lw=2, label=label)
            rows = dri[(dri["case"] == case) & (dri["task"] == task) & dri["reached"]]
            for _, row in rows[rows["probability"].isin(marks)].iterrows():
                ax.plot(
                    row["range_m"] / 1e3,
                    row["probability"],
                    "o",
                    color=colour,
                    ms=6,
                    mec="black",
                    mew=0.6,
                )
    for p in marks:
        ax.axhline(p, color="0.6", lw=0.8, ls=":")
        ax.annotate(
            f"{p:.0%}",
            (km[-1], p),
            xytext=(2, 0),
            textcoords="offset points",
            va="center",
            fontsize=8,
            color="0.4",
            annotation_clip=False,
        )
    ax.set_xlim(0, km[-1])
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("slant range [km]")
    ax.set_ylabel("probability")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8, ncol=1 if len(cases) == 1 else 2)
    ax.set_title(title or "Range performance (dots: DRI ranges)")
    return fig


def plot_transforms(criterion: Any = "johnson", title: str | None = None) -> Figure:
    """The transforms against cycles on a log axis, as Figs. 3.5 and 3.7 of Sonesson (2004).

    Left: C2NVEO (Table 3.3, the band between the optimistic and pessimistic curves, the
    nominal curve drawn) with the TTPF for the criterion's N50s. Right: Schmieder–Weathersby
    (Table 3.5) by clutter region with the TTPF for detection.
    """
    crit = get_criterion(criterion)
    n = np.logspace(-2, np.log10(30.0), 600)
    fig = Figure(figsize=(11.0, 4.6), dpi=100, layout="constrained")
    left, right = fig.subplots(1, 2, sharey=True)
    reference = get_criterion("c2nveo")
    for task, colour in TASK_COLOURS.items():
        n50 = reference.n50(task)
        low = transforms.c2nveo(n, n50, task, "optimistic")
        high = transforms.c2nveo(n, n50, task, "pessimistic")
        left.fill_between(n, low, high, color=colour, alpha=0.18, lw=0)
        left.plot(
            n,
            transforms.c2nveo(n, n50, task, "nominal"),
            color=colour,
            lw=2,
            label=f"C2NVEO {task}",
        )
        if task in crit.tasks:
            left.plot(
                n,
                transforms.ttpf(n, crit.n50(task)),
                "--",
                color=colour,
                lw=1.5,
                label=f"TTPF {task} (N50 {crit.n50(task):g})",
            )
    left.set_title("C2NVEO (Table 3.3, band: optimistic–pessimistic) and TTPF")
    for region, colour in REGION_COLOURS.items():
        right.plot(
            n,
            transforms.schmieder_weathersby(n, region=region),
            color=colour,
            lw=2,
            label=f"{region} clutter",
        )
    if "detection" in crit.tasks:
        right.plot(
            n,
            transforms.ttpf(n, crit.n50("detection")),
            "--",
            color=TASK_COLOURS["detection"],
            lw=1.5,
            label=f"TTPF detection (N50 {crit.n50('detection'):g})",
        )
    right.set_title("Schmieder–Weathersby detection (Table 3.5)")
    for ax in (left, right):
        ax.set_xscale("log")
        ax.set_xlim(n[0], n[-1])
        ax.set_ylim(0, 1.02)
        ax.set_xlabel("cycles across the critical dimension [line pairs]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    left.set_ylabel("probability")
    fig.suptitle(title or f"Resolution-to-probability transforms (criterion {crit.name})")
    return fig


def plot_atmosphere(
    band: Any = "lwir", max_range: float = 10e3, level: str = "nominal", title: str | None = None
) -> Figure:
    """Transmittance (7.3) and SNR (7.7) against range for each obscurant of Table 7.1.

    Parameters
    ----------
    band : str or (float, float)
        A Table 7.1 band.
    max_range : float
        Largest range [m], > 0.
    level : {"low", "nominal", "high"}
        Which point of each Table 7.1 cell.
    """
    if not max_range > 0:
        raise ValueError(f"max_range must be > 0 m, got {max_range!r}")
    name = band_name(band)
    low, high = band_limits(band)
    r = np.linspace(0.0, max_range, 500)
    fig = Figure(figsize=(11.0, 4.6), dpi=100, layout="constrained")
    left, right = fig.subplots(1, 2, sharex=True)
    colours = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b")
    for colour, obscurant in zip(colours, atmosphere.OBSCURANTS, strict=False):
        gamma = atmosphere.obscurant_extinction(obscurant, name, level)
        tau = atmosphere.transmittance(gamma, r)
        label = f"{obscurant} ({gamma * 1e3:.3g} Np/km)"
        left.plot(r / 1e3, tau, color=colour, lw=2, label=label)
        right.plot(r / 1e3, atmosphere.snr_from_transmittance(tau), color=colour, lw=2, label=label)
    left.set_ylabel("transmittance τ")
    left.set_ylim(0, 1.02)
    right.set_ylabel("SNR [dB]  (Eq. 7.7)")
    right.set_ylim(-60, 60)
    right.axhline(0.0, color="0.5", lw=0.8, ls=":")
    for ax in (left, right):
        ax.set_xlabel("range [km]")
        ax.set_xlim(0, max_range / 1e3)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    fig.suptitle(
        title
        or f"Atmosphere, Table 7.1 {level} extinction, {name} band "
        f"({low * 1e6:g}–{high * 1e6:g} µm)"
    )
    return fig


def save_figure(fig: Figure, path: str | Path) -> Path:
    """Write a figure as PNG or SVG (by the file's suffix), atomically
    (:func:`targetacq.outputs.write_atomically`).

    Raises
    ------
    ValueError
        If the folder does not exist, the suffix is not .png or .svg, or (``OutputError``) the
        file cannot be written: the message names the file and the reason.
    """
    out, kind = output_path(path, FIGURE_FORMATS, "figure file")
    return write_atomically(out, lambda p: fig.savefig(p, format=kind))


PLOT_KINDS: Mapping[str, Callable[..., Figure]] = MappingProxyType(
    {"curves": plot_range_performance, "transforms": plot_transforms, "atmosphere": plot_atmosphere}
)
"""Figure kinds of ``targetacq plot``, by name."""
