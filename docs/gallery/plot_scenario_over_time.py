"""
A scenario evaluated over time
==============================

The bundled scenario ``uav_haze.toml``: a UAV's long-wave camera flies east at 1.5 km over a
truck, a tank and a moving jeep in high haze. :class:`targetacq.run.model_chain.ModelChain` evaluates
every sensor × target × time in one pass (:func:`targetacq.example_path` finds the bundled file); the fused detection probability of each target rises
as the UAV closes in and drops when the target leaves the field of view.
"""

import matplotlib.pyplot as plt
import numpy as np

from targetacq import example_path
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario

scenario = load_scenario(example_path("uav_haze"))
chain = ModelChain(scenario)
dataset = chain.evaluate(np.arange(0.0, 120.5, 1.0)).dataset

fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
for target in dataset["target"].values:
    p = dataset["fused_detection"].sel(target=target)
    ax.plot(dataset["time"], p, label=str(target))
ax.set_xlabel("time [s]")
ax.set_ylabel("P(detection), fused over sensors")
ax.set_ylim(0, 1)
ax.grid(True, alpha=0.3)
_ = ax.legend()

# %%
# The peak of each task over time:

print(dataset[["fused_detection", "fused_recognition"]].max("time").to_dataframe().round(3))
