"""
Range performance of the example camera, clear air and haze
===========================================================

The bundled example camera — 640 × 512 pixels of 17 µm behind a 75 mm lens, one cycle
= two pixels = 0.453 mrad — looking at the NATO standard target (critical dimension 2.3 m),
once through clear air and once through high haze (Table 7.1, 8–12 µm, high end of the cell),
with a medium clutter (SCR 3). The haze both attenuates the contrast and adds the noise of
Eq. (7.7), so every task's range shrinks.
"""

import numpy as np

import targetacq as ta
from targetacq.core.cases import RangeCase
from targetacq.reports.plots import plot_range_performance
from targetacq.core.ranges import range_performance

ifov = ta.ifov(17e-6, 75e-3)  # [rad]
haze = ta.obscurant_extinction("haze", "lwir", "high")  # [Np/m]
cases = {
    "clear": RangeCase(2.3, ifov, scr=3.0),
    "high haze": RangeCase(2.3, ifov, scr=3.0, extinction=haze),
}
performance = range_performance(np.linspace(100.0, 8000.0, 200), cases, [0.5, 0.8])

# %%
# The DRI ranges at 50 % and 80 %, the dots on the curves:

table = performance.dri.pivot_table(
    index=["case", "probability"], columns="task", values="range_m"
).round(0)
print(table)

# %%
fig = plot_range_performance(performance, title="Example camera, 2.3 m target, SCR 3")
