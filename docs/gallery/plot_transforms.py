"""
Transforms: TTPF, C2NVEO and Schmieder–Weathersby
=================================================

Johnson's criterion gives the 50 % point of each task; the transform gives the shape of the
curve around it. The TTPF is smooth; the C2NVEO curves (Table 3.3) come with an optimistic and
a pessimistic bound; the Schmieder–Weathersby curves (Table 3.5) give detection in low, medium
and high clutter. The cycles axis is logarithmic, as in the thesis's figures.
"""

import numpy as np

import targetacq as ta
from targetacq.reports.plots import plot_transforms

fig = plot_transforms("johnson")

# %%
# The same numbers, read from the transforms directly: detection at 1 and 2 cycles.

for n in (1.0, 2.0):
    ttpf = ta.transform(n, 1.0, "detection", "ttpf")
    c2nveo = ta.transform(n, 1.0, "detection", "c2nveo")
    high = ta.transform(n, 1.0, "detection", "schmieder-weathersby", region="high")
    print(f"N = {n}: TTPF {ttpf:.2f}, C2NVEO {c2nveo:.2f}, S-W high clutter {high:.2f}")

# %%
# A continuous SCR blends the Table 3.5 curves in log SCR, so the probability does not jump at
# the region edges:

scr = np.geomspace(0.2, 20.0, 7)
print(np.round(ta.schmieder_weathersby(1.5, 1.0, scr=scr), 3))
