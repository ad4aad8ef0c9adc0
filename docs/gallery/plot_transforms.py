"""
Transforms from cycles to probability
=====================================

The same Johnson criterion read through three transforms.
"""

import targetacq.plots as plots

fig = plots.plot_transforms("johnson")
