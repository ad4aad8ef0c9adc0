"""Figures: range-performance curves, the transforms, the atmosphere, scenario timelines and
simulated first times (matplotlib, headless).

Figures are built with :class:`matplotlib.figure.Figure` directly, never through pyplot, so no
display or global state is involved. :data:`PLOT_KINDS` is the registry of the CLI's
``targetacq plot KIND``. Colours are fixed per task so that a reader can follow a task across
figures; line styles tell cases (or sensors) apart. Legends sit below the axes, never on the
data.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from targetacq.acquisition import transforms
from targetacq.acquisition.criteria import get_criterion
from targetacq.io.files import output_path, write_atomically
from targetacq.physics import atmosphere
from targetacq.physics.bands import band_limits, band_name

__all__ = [
    "FIGURE_FORMATS",
    "PLOT_KINDS",
    "TASK_COLOURS",
    "plot_atmosphere",
    "plot_first_times",
    "plot_range_performance",
    "plot_timeline",
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
_LINESTYLES: tuple[Any, ...] = (
    "-",
    "--",
    ":",
    "-.",
    (0, (8, 2, 1, 2, 1, 2)),
    (0, (1, 4)),
    (0, (12, 3)),
    (0, (5, 1, 1, 1, 1, 1, 1, 1)),
)
"""Line styles of the cases (sensors) of a figure, in turn."""
FIGURE_FORMATS = ("png", "svg")


def _linestyle(k: int) -> Any:
    return _LINESTYLES[k % len(_LINESTYLES)]


def _legend_below(fig: Figure, handles: Sequence[Any], ncol: int) -> None:
    """One legend for the figure, below its axes (constrained layout makes room for it)."""
    fig.legend(
        handles=list(handles),
        loc="outside lower center",
        ncol=max(1, min(ncol, len(handles))),
        fontsize=8,
        frameon=False,
    )


def _task_handles(tasks: Sequence[str], style: Any = "-") -> list[Line2D]:
    return [Line2D([], [], color=TASK_COLOURS[t], lw=2, ls=style, label=t) for t in tasks]


def plot_range_performance(
    performance: Any,
    title: str | None = None,
    probabilities: Sequence[float] | None = None,
    labels: Mapping[str, str] | None = None,
    requirement: tuple[float, float | None] | None = None,
) -> Figure:
    """P(detection), P(recognition), P(identification) against range, with DRI ranges marked.

    Colour tells the task, line style the case; the legend is below the axes. Where the curves
    carry bands (``<task>_p05`` and ``<task>_p95``, and the DRI table ``range_p05_m`` and
    ``range_p95_m``: :func:`targetacq.reports.content.with_uncertainty`), each curve's 5–95 %
    band is shaded and each DRI dot has a bar from its 5 % to its 95 % range.

    Parameters
    ----------
    performance : targetacq.core.ranges.RangePerformance
        From :func:`targetacq.core.ranges.range_performance`.
    title : str, optional
        The sensor, target and conditions, e.g. "640×512 17 µm, f = 75 mm — 2.3 m target".
    probabilities : sequence of float, optional
        Which DRI probabilities to mark (default: all in ``performance.dri``).
    labels : mapping, optional
        Case → text for the legend (default: the case names).
    requirement : (float, float or None), optional
        A range [m] and the probability a task must reach there (or None): a dashed vertical
        line at the range and a star at the probability.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from targetacq.core.cases import RangeCase
    >>> from targetacq.core.ranges import range_performance
    >>> perf = range_performance([500.0, 5000.0], {"clear": RangeCase(2.3, 2e-4)}, [0.5])
    >>> plot_range_performance(perf, title="2.3 m target").axes[0].get_title()
    '2.3 m target'
    """
    curves, dri = performance.curves, performance.dri
    km = curves["range"].values / 1e3
    cases = [str(c) for c in curves["case"].values]
    names = {c: (labels or {}).get(c, c) for c in cases}
    ncol = 4 if len(cases) <= 2 else 3
    entries = 4 + (len(cases) if len(cases) > 1 else 0)
    rows = -(-entries // ncol)
    fig = Figure(figsize=(8.0, 5.2 + 0.2 * rows), dpi=100, layout="constrained")
    ax = fig.add_subplot()
    marks = sorted(set(dri["probability"])) if probabilities is None else list(probabilities)
    banded = any(f"{task}_p05" in curves for task in TASK_COLOURS)
    for k, case in enumerate(cases):
        for task, colour in TASK_COLOURS.items():
            if task not in curves:
                continue
            if f"{task}_p05" in curves:  # the 5–95 % band (targetacq.reports.content)
                ax.fill_between(
                    km,
                    curves[f"{task}_p05"].sel(case=case).values,
                    curves[f"{task}_p95"].sel(case=case).values,
                    color=colour,
                    alpha=0.18,
                    lw=0,
                )
            ax.plot(
                km,
                curves[task].sel(case=case).values,
                ls=_linestyle(k),
                color=colour,
                lw=2,
                label=f"{task} — {names[case]}",
            )
            rows = dri[(dri["case"] == case) & (dri["task"] == task) & dri["reached"]]
            for _, row in rows[rows["probability"].isin(marks)].iterrows():
                if "range_p05_m" in row and np.isfinite(row["range_m"]):
                    low = row["range_p05_m"] if np.isfinite(row["range_p05_m"]) else 0.0
                    high = min(row["range_p95_m"], km[-1] * 1e3)
                    ax.plot(
                        [low / 1e3, high / 1e3],
                        [row["probability"]] * 2,
                        color=colour,
                        lw=1.2,
                        marker="|",
                        ms=8,
                    )
                if np.isfinite(row["range_m"]):
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
    handles: list[Any] = _task_handles([t for t in TASK_COLOURS if t in curves])
    handles.append(
        Line2D([], [], ls="none", marker="o", color="0.5", mec="black", label="DRI range")
    )
    if banded:
        handles.append(Patch(color="0.5", alpha=0.35, lw=0, label="5–95 % band"))
    if requirement is not None:
        at, needed = requirement
        ax.axvline(at / 1e3, color="black", lw=1.2, ls="--")
        text = f"requirement: {at / 1e3:g} km" + ("" if needed is None else f", P ≥ {needed:g}")
        if needed is not None:
            ax.plot(at / 1e3, needed, "*", color="black", ms=14, zorder=5)
        handles.append(
            Line2D([], [], color="black", lw=1.2, ls="--", marker="*", ms=10, label=text)
        )
    if len(cases) > 1:
        handles += [
            Line2D([], [], color="black", lw=1.5, ls=_linestyle(k), label=names[case])
            for k, case in enumerate(cases)
        ]
    _legend_below(fig, handles, ncol)
    ax.set_title(title or "Range performance (dots: DRI ranges)", fontsize=10)
    return fig


def plot_transforms(criterion: Any = "johnson", title: str | None = None) -> Figure:
    """The transforms against cycles on a log axis, as Figs. 3.5 and 3.7 of Sonesson (2004).

    Left: C2NVEO (Table 3.3, the band between the optimistic and pessimistic curves, the
    nominal curve drawn) with the TTPF for the criterion's N50s. Right: Schmieder–Weathersby
    (Table 3.5) by clutter region with the TTPF for detection.
    """
    crit = get_criterion(criterion)
    n = np.logspace(-2, np.log10(30.0), 600)
    fig = Figure(figsize=(11.0, 5.4), dpi=100, layout="constrained")
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
    left.set_title("C2NVEO (Table 3.3, band: optimistic–pessimistic) and TTPF", fontsize=10)
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
    right.set_title("Schmieder–Weathersby detection (Table 3.5)", fontsize=10)
    for ax in (left, right):
        ax.set_xscale("log")
        ax.set_xlim(n[0], n[-1])
        ax.set_ylim(0, 1.02)
        ax.set_xlabel("cycles across the critical dimension [line pairs]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(
            fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False
        )
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
    title : str, optional
        Default: the band and the level.

    Examples
    --------
    >>> plot_atmosphere("lwir", 5e3)._suptitle.get_text()
    'Atmosphere, Table 7.1 nominal extinction, lwir band (8–12 µm)'
    """
    if not max_range > 0:
        raise ValueError(f"max_range must be > 0 m, got {max_range!r}")
    name = band_name(band)
    low, high = band_limits(band)
    r = np.linspace(0.0, max_range, 500)
    fig = Figure(figsize=(11.0, 5.0), dpi=100, layout="constrained")
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
    handles, _ = left.get_legend_handles_labels()
    _legend_below(fig, handles, 6)
    fig.suptitle(
        title
        or f"Atmosphere, Table 7.1 {level} extinction, {name} band "
        f"({low * 1e6:g}–{high * 1e6:g} µm)"
    )
    return fig


def plot_timeline(dataset: Any, title: str | None = None) -> Figure:
    """Probabilities over time per target: each sensor's, and the fused ones (Eq. (8.4)).

    One panel per target; colour tells the task; thin broken lines are the sensors, the thick
    solid line the sensor-level fusion (drawn where there are two sensors or more, the
    ``fused_<task>`` variables of the dataset).

    Parameters
    ----------
    dataset : xarray.Dataset
        :meth:`targetacq.run.model_chain.ModelChain.evaluate` ``.dataset``: ``<task>`` over (sensor,
        target, time), ``fused_<task>`` over (target, time).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Each line's label is ``"<task> — <sensor>"`` or ``"<task> — fused"``.
    """
    tasks = [t for t in TASK_COLOURS if t in dataset]
    sensors = [str(s) for s in dataset["sensor"].values]
    targets = [str(g) for g in dataset["target"].values]
    fused = len(sensors) > 1
    t = np.asarray(dataset["time"].values, dtype=float)
    fig = Figure(figsize=(8.0, 1.0 + 2.2 * len(targets)), dpi=100, layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(targets), 1, sharex=True, squeeze=False)[:, 0])
    for ax, target in zip(axes, targets, strict=True):
        for task in tasks:
            colour = TASK_COLOURS[task]
            for k, sensor in enumerate(sensors):
                ax.plot(
                    t,
                    dataset[task].sel(sensor=sensor, target=target).values,
                    ls=_linestyle(k + 1) if fused else "-",
                    color=colour,
                    lw=1.2 if fused else 2,
                    label=f"{task} — {sensor}",
                )
            if fused:
                ax.plot(
                    t,
                    dataset[f"fused_{task}"].sel(target=target).values,
                    "-",
                    color=colour,
                    lw=2.4,
                    label=f"{task} — fused",
                )
        ax.set_ylim(0, 1.02)
        ax.set_xlim(t[0], t[-1])
        ax.set_ylabel("probability")
        ax.set_title(target, fontsize=9, loc="left")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    handles: list[Any] = _task_handles(tasks)
    if fused:
        handles.append(Line2D([], [], color="black", lw=2.4, label="fused (Eq. 8.4)"))
    handles += [
        Line2D([], [], color="black", lw=1.2, ls=_linestyle(k + 1) if fused else "-", label=s)
        for k, s in enumerate(sensors)
    ]
    _legend_below(fig, handles, 4)
    fig.suptitle(
        title
        or (
            "Probabilities over time, per sensor and fused"
            if fused
            else f"Probabilities over time ({sensors[0]})"
        ),
        fontsize=11,
    )
    return fig


def plot_first_times(result: Any, title: str | None = None) -> Figure:
    """Distributions of the first time of each task per target, from a simulation.

    The empirical CDF over the runs of the first time (fused over the sensors) at which each
    target was detected, recognised and identified; a curve ending below 1 means some runs never
    got there within the simulated duration.

    Parameters
    ----------
    result : targetacq.run.search.SimulationResult
        From :func:`targetacq.run.search.simulate`.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    targets = list(result.targets)
    tasks = [t for t in TASK_COLOURS if t in result.fused]
    ncols = min(3, len(targets))
    nrows = -(-len(targets) // ncols)
    fig = Figure(figsize=(3.6 * ncols + 0.6, 1.2 + 2.6 * nrows), dpi=100, layout="constrained")
    axes = fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False).ravel()
    for g, target in enumerate(targets):
        ax = axes[g]
        for task in tasks:
            first = np.asarray(result.fused[task][:, g], dtype=float)
            runs = first.size
            hit = np.sort(first[np.isfinite(first)])
            x = np.concatenate([[0.0], hit, [result.duration]])
            y = np.concatenate([[0.0], np.arange(1, hit.size + 1) / runs, [hit.size / runs]])
            ax.step(x, y, where="post", color=TASK_COLOURS[task], lw=2, label=task)
        ax.set_title(target, fontsize=9, loc="left")
        ax.set_xlim(0, result.duration)
        ax.set_ylim(0, 1.02)
        ax.grid(True, alpha=0.3)
    for ax in axes[len(targets) :]:
        ax.set_visible(False)
    for ax in axes[(nrows - 1) * ncols :]:
        ax.set_xlabel("time from start [s]")
    for ax in axes[::ncols]:
        ax.set_ylabel("share of runs")
    _legend_below(fig, _task_handles(tasks), 3)
    fig.suptitle(title or "First times (fused over the sensors): share of runs", fontsize=11)
    return fig


def save_figure(fig: Figure, path: str | Path) -> Path:
    """Write a figure as PNG or SVG (by the file's suffix), atomically
    (:func:`targetacq.io.files.write_atomically`).

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
