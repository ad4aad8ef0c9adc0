"""From cycles on target to probabilities: criteria (N50), the transforms, the path noise's
effect on them, fusion over sensors, and what an engagement keeps over time.

Imports :mod:`targetacq.base` only: these are the Johnson-style laws, independent of how the
cycles and the SNR were found.
"""
