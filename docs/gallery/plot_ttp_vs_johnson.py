"""
TTP metric against Johnson's criteria
=====================================

The same thermal camera (17 µm pixels, 100 mm lens, NETD 50 mK, 10 µm) and the same 2.3 m
vehicle, ranged two ways: Johnson's criteria (cycles on target from the pixels and the optics
limit, the NETD as a separate SNR) and the TTP metric (the contrast against the observer's
threshold through the system MTF and noise, V50s of ``ttp-vehicles``). Left: identification
range against the target's ΔT at f/1; right: against the f-number at ΔT = 2 K.
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

from targetacq.core.cases import RangeCase
from targetacq.core.ranges import dri_ranges
from targetacq.physics.ttp import TtpSystem

IFOV, FOCAL, WAVELENGTH, NETD = 17e-6 / 0.1, 0.1, 10e-6, 0.05


def ranges(delta_t, f_number):
    """Identification range [m] by Johnson and by TTP."""
    aperture = FOCAL / f_number
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        johnson = RangeCase(2.3, IFOV, wavelength=WAVELENGTH, aperture=aperture,
                            contrast=delta_t, noise_equivalent_contrast=NETD)  # fmt: skip
        ttp = RangeCase(2.3, IFOV, ttp=TtpSystem(IFOV, aperture, WAVELENGTH, NETD),
                        contrast=delta_t)  # fmt: skip
        return (float(dri_ranges(johnson)["identification"]),
                float(dri_ranges(ttp)["identification"]))  # fmt: skip


delta_t = np.geomspace(0.03, 10.0, 12)
f_numbers = np.array([0.8, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6, 8.0])
by_dt = np.array([ranges(dt, 1.0) for dt in delta_t])
by_f = np.array([ranges(2.0, f) for f in f_numbers])

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
for ax, x, found, label in ((left, delta_t, by_dt, "ΔT [K]"), (right, f_numbers, by_f, "f-number")):
    ax.plot(x, found[:, 0], "o-", label="Johnson (N50 6.4, TTPF)")
    ax.plot(x, found[:, 1], "s-", label="TTP metric (V50 20.8)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(label)
    ax.grid(True, which="both", alpha=0.3)
right.set_xticks(f_numbers, labels=[f"{f:g}" for f in f_numbers])
right.minorticks_off()
left.set_ylabel("identification range at P = 0.5 [m]")
left.legend()
fig.suptitle("Same camera, same target: Johnson's criteria and the TTP metric")

# %%
# The numbers behind the figure:

for dt, (j, t) in zip(delta_t[::3], by_dt[::3], strict=True):
    print(f"ΔT {dt:5.2f} K: Johnson {j:6.0f} m, TTP {t:6.0f} m")
