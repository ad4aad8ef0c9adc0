"""Physical constants, taken from :mod:`scipy.constants` (CODATA) and derived, never retyped."""

from __future__ import annotations

import math

from scipy import constants as _c

__all__ = [
    "BOLTZMANN",
    "FIRST_RADIATION_CONSTANT",
    "PLANCK",
    "SECOND_RADIATION_CONSTANT",
    "SPEED_OF_LIGHT",
    "STEFAN_BOLTZMANN",
    "WIEN_DISPLACEMENT",
]

PLANCK: float = _c.h
"""Planck constant h [J s]."""

SPEED_OF_LIGHT: float = _c.c
"""Speed of light in vacuum c [m/s]."""

BOLTZMANN: float = _c.k
"""Boltzmann constant k [J/K]."""

STEFAN_BOLTZMANN: float = _c.Stefan_Boltzmann
"""Stefan–Boltzmann constant σ [W m⁻² K⁻⁴]."""

FIRST_RADIATION_CONSTANT: float = 2.0 * math.pi * PLANCK * SPEED_OF_LIGHT**2
"""c1 = 2π h c² [W m²] of Planck's law for exitance, Eq. (6.2) (the erratum to (6.12))."""

SECOND_RADIATION_CONSTANT: float = PLANCK * SPEED_OF_LIGHT / BOLTZMANN
"""c2 = h c / k [m K]."""

WIEN_DISPLACEMENT: float = _c.Wien
"""Wien wavelength displacement constant b [m K]: λ_peak = b / T."""
