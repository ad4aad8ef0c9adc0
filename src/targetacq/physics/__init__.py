"""The physics kernels: geometry, optics, radiometry, bands, atmosphere, clutter, terrain,
MRTD, detector noise and the radar and laser-radar equations.

Pure, vectorised, broadcasting functions of SI floats; they import :mod:`targetacq.base` and
:mod:`targetacq.acquisition.probabilities` only.
"""
