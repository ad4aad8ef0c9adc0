"""
Atmosphere: transmittance and SNR against range, per band
=========================================================

Beer–Lambert transmittance (Eq. (7.3)) and the SNR the thesis assigns to the lost part of the
signal (Eq. (7.7)) for every obscurant of Table 7.1, at the geometric mean of each cell, in
the long-wave band; then haze in all three bands.
"""

import matplotlib.pyplot as plt
import numpy as np

import targetacq as ta
from targetacq.physics.bands import BANDS
from targetacq.reports.plots import plot_atmosphere

fig = plot_atmosphere("lwir", max_range=10e3)

# %%
# Haze in each band of Table 7.1: the visible band suffers most.

r = np.linspace(0.0, 10e3, 300)
fig2, ax = plt.subplots(figsize=(7, 4), layout="constrained")
for band in BANDS:
    gamma = ta.obscurant_extinction("haze", band)
    ax.plot(r / 1e3, ta.snr_from_transmittance(ta.transmittance(gamma, r)), label=band)
ax.set_xlabel("range [km]")
ax.set_ylabel("SNR of Eq. (7.7) [dB]")
ax.set_ylim(-40, 40)
ax.grid(True, alpha=0.3)
_ = ax.legend(title="haze, nominal")
