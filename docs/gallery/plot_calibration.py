"""
Calibrating N50 and the exponent to trials
==========================================

Recognition trials (synthetic here: 150 trials drawn from a TTPF with N50 = 4.5 cycles and an
exponent of 4.5 at N50, steeper than the registered TTPF's 3.4) are fitted by maximum
likelihood (:func:`targetacq.acquisition.calibration.fit_criterion`). The figure shows the
outcomes binned by cycles (the share of successes in each bin, with its binomial standard
error), the fitted curve with its pointwise 90 % profile-likelihood band, and Johnson's
average (N50 = 4, the registered TTPF) for comparison.
"""

import matplotlib.pyplot as plt
import numpy as np

import targetacq as ta

rng = np.random.default_rng(2004)
cycles = rng.uniform(1.5, 9.0, 150)
x = cycles / 4.5
truth = 1.0 / (1.0 + np.exp(-(4.5 / 3.4) * (2.7 + 0.7 * x) * np.log(x)))
seen = (rng.random(cycles.size) < truth).astype(int)

fit = ta.fit_criterion(cycles, seen, "recognition")

edges = np.arange(1.5, 9.01, 1.0)
which = np.digitize(cycles, edges) - 1
middles, shares, errors = [], [], []
for k in range(edges.size - 1):
    outcomes = seen[which == k]
    if outcomes.size:
        share = outcomes.mean()
        middles.append(cycles[which == k].mean())
        shares.append(share)
        errors.append(np.sqrt(share * (1.0 - share) / outcomes.size))

n = np.linspace(0.5, 12.0, 300)
low, high = fit.probability_interval(n)
fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
ax.fill_between(n, low, high, color="C0", alpha=0.25, label="90 % profile-likelihood band")
ax.plot(n, fit.probability(n), "C0", label=f"fit: N50 {fit.n50:.2f}, E50 {fit.exponent:.2f}")
ax.plot(n, ta.ttpf(n, 4.0), "k--", lw=1, label="Johnson's average: N50 4, E50 3.4")
ax.errorbar(middles, shares, yerr=errors, fmt="o", color="C1", capsize=3,
            label="trials: share seen per 1-cycle bin")  # fmt: skip
ax.set_xlabel("cycles on target N")
ax.set_ylabel("P(recognition)")
ax.set_ylim(-0.02, 1.02)
ax.grid(True, alpha=0.3)
ax.legend(loc="lower right")

# %%
# The fit, its 90 % intervals, and the criterion (Johnson's averages for the other tasks;
# with ``fit_exponent=False``, ``name="my-trials"`` would register its N50 under that name):

print(f"N50 {fit.n50:.2f} cycles, 90 % interval {fit.n50_interval[0]:.2f} to "
      f"{fit.n50_interval[1]:.2f}")  # fmt: skip
print(f"E50 {fit.exponent:.2f}, 90 % interval {fit.exponent_interval[0]:.2f} to "
      f"{fit.exponent_interval[1]:.2f}")  # fmt: skip
print(f"log-likelihood {fit.log_likelihood:.2f} over {fit.trials} trials")
print(dict(fit.criterion.thresholds))
