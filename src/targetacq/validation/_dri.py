"""A vendor's published DRI ranges against the model's.

Source: Hikvision, *Thermometric Network Positioning System DS-2TD8166-180ZE2F/V2, Quick Start
Guide*, §2.3.1 "Monitoring Distance Range", Tables 2-1 (pixel interval 17 µm) and 2-2 (25 µm),
https://www.manualshelf.com/manual/hikvision/ds-2td8166-180ze2f-v2/quick-start-guide-english/page-14.html.
The guide states the probability (50 %), the targets (vehicle 2.3 m; a person 1.8 m × 0.5 m,
"human width cannot exceed 0.75 m") and prints ranges to the metre and IFOVs in mrad. Its ranges
are those of the thermal-camera pixel rule, 1.5 / 6 / 12 pixels across a 2.3 m or 0.75 m
critical dimension, which is the package's ``pixels-1.5-6-12`` criterion.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from targetacq.core import ranges
from targetacq.physics import optics
from targetacq.reports.plots import TASK_COLOURS
from targetacq.validation._model import Check, Section, as_float, half_unit, new_figure

__all__ = ["VENDOR_SOURCE", "vendor_section"]

VENDOR_SOURCE = (
    "Hikvision, Thermometric Network Positioning System DS-2TD8166-180ZE2F/V2, Quick Start "
    "Guide, §2.3.1, Tables 2-1 and 2-2 (www.manualshelf.com/manual/hikvision/"
    "ds-2td8166-180ze2f-v2/quick-start-guide-english/page-14.html)"
)

_CRITERION = "pixels-1.5-6-12"
_TARGETS = {"vehicle": 2.3, "human": 0.75}  # critical dimension [m]
_FOCAL_MM = ("75", "100", "150")

# Pixel pitch [µm] → (IFOV printed "MRAD" per focal length, {(task, target): ranges [m]}).
_PRINTED: dict[str, tuple[tuple[str, ...], dict[tuple[str, str], tuple[str, ...]]]] = {
    "17": (
        ("0.23", "0.17", "0.11"),
        {
            ("detection", "vehicle"): ("6765", "9020", "13529"),
            ("detection", "human"): ("2206", "2941", "4412"),
            ("recognition", "vehicle"): ("1691", "2255", "3382"),
            ("recognition", "human"): ("551", "735", "1103"),
            ("identification", "vehicle"): ("846", "1127", "1691"),
            ("identification", "human"): ("276", "368", "551"),
        },
    ),
    "25": (
        ("0.33", "0.25", "0.17"),
        {
            ("detection", "vehicle"): ("4600", "6133", "9200"),
            ("detection", "human"): ("1500", "2000", "3000"),
            ("recognition", "vehicle"): ("1150", "1533", "2300"),
            ("recognition", "human"): ("375", "500", "750"),
            ("identification", "vehicle"): ("575", "767", "1150"),
            ("identification", "human"): ("188", "250", "375"),
        },
    ),
}


def _model_ranges(pitch_m: float, focal_m: Any, critical_dimension: float) -> dict[str, Any]:
    ifov = optics.ifov(pitch_m, focal_m)
    return ranges.dri_ranges(ranges.RangeCase(critical_dimension, ifov, criterion=_CRITERION), 0.5)


def vendor_section() -> Section:
    """A vendor's DRI table: IFOV and the 50 % ranges of two targets with three lenses."""
    checks = []
    for pitch, (mrad, table) in _PRINTED.items():
        pitch_m = float(pitch) * 1e-6
        for focal, printed in zip(_FOCAL_MM, mrad, strict=True):
            checks.append(
                Check(
                    f"{pitch} µm, {focal} mm: IFOV",
                    float(printed),
                    as_float(optics.ifov(pitch_m, float(focal) * 1e-3)) * 1e3,
                    half_unit(printed),
                    "mrad",
                    printed,
                )
            )
        for (task, target), printed_ranges in table.items():
            for focal, printed in zip(_FOCAL_MM, printed_ranges, strict=True):
                found = _model_ranges(pitch_m, float(focal) * 1e-3, _TARGETS[target])
                checks.append(
                    Check(
                        f"{pitch} µm, {focal} mm, {target} ({_TARGETS[target]:g} m): {task}",
                        float(printed),
                        as_float(found[task]),
                        half_unit(printed),
                        "m",
                        printed,
                    )
                )
    return Section(
        key="vendor-dri",
        title="A vendor's DRI ranges (thermal camera datasheet)",
        source=VENDOR_SOURCE + ". The guide states P = 50 %, a vehicle of 2.3 m and a person "
        "whose width 'cannot exceed 0.75 m'.",
        method="targetacq.core.ranges.dri_ranges(RangeCase(d, targetacq.physics.optics.ifov(pitch, "
        "focal "
        f"length), criterion='{_CRITERION}'), 0.5) (the TTPF's 50 % point, 1.5 / 6 / 12 "
        "pixels = 0.75 / 3 / 6 cycles), d = 2.3 m (vehicle) or 0.75 m (person).",
        checks=tuple(checks),
        notes="No atmosphere, clutter or optics limit: the datasheet assumes fine weather and "
        "normal visibility. The vendor's numbers are the pixel rule's closed form, rounded to the "
        "metre: 187.5 m printed as 188 is a round-half-up at the edge of the ±0.5 m tolerance. "
        "A datasheet is the product of the same rule, so this checks the model's inverse and "
        "units against an independent calculation, not the rule itself against field trials.",
        figure=_vendor_figure,
    )


def _vendor_figure() -> Figure:
    focal_mm = np.linspace(50.0, 170.0, 121)
    fig, axes = new_figure(11.0, 4.2, 2, top=0.55)
    for ax, (pitch, (_, table)) in zip(axes, _PRINTED.items(), strict=True):
        pitch_m = float(pitch) * 1e-6
        for target, d in _TARGETS.items():
            style = "-" if target == "vehicle" else "--"
            found = _model_ranges(pitch_m, focal_mm * 1e-3, d)
            for task, colour in TASK_COLOURS.items():
                ax.plot(focal_mm, found[task], style, color=colour, lw=1.8)
                printed = [float(r) for r in table[task, target]]
                ax.plot([float(f) for f in _FOCAL_MM], printed, "o", color=colour, mec="black")
        ax.set_yscale("log")
        ax.set_xlabel("focal length [mm]")
        ax.set_title(f"{pitch} µm pixels")
        ax.grid(True, which="both", alpha=0.3)
    for task, colour in TASK_COLOURS.items():
        axes[0].plot([], [], color=colour, lw=1.8, label=task)
    axes[0].plot([], [], "-", color="0.3", label="model, vehicle 2.3 m")
    axes[0].plot([], [], "--", color="0.3", label="model, person 0.75 m")
    axes[0].plot([], [], "o", color="0.6", mec="black", label="datasheet (printed)")
    axes[0].set_ylabel("range at P = 0.5 [m]")
    axes[0].legend(fontsize=8, loc="lower right", ncol=2)
    fig.suptitle("Datasheet DRI ranges and the model's")
    return fig
