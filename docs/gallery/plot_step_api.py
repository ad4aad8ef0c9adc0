"""
The step API in a loop
======================

A simulation that moves sensors and targets itself calls :class:`targetacq.Simulation` once per
step. Here a mast-mounted thermal camera watches a truck and a jeep driving towards it at 10 Hz
for one minute; each step returns the probabilities at that moment and the random events
(first detection, recognition, identification) that happened within the step.
"""

import matplotlib.pyplot as plt
import numpy as np

import targetacq as ta

sim = ta.Simulation(
    sensors=[
        {
            "name": "mast",
            "band": "lwir",
            "ifov": 0.25e-3,
            "pixels": (640, 480),
            "azimuth": np.radians(90.0),
            "depression": np.radians(0.5),
        }
    ],
    targets=[
        {"name": "truck", "dimensions": (7.0, 2.5, 3.0), "temperature": 305.0},
        {"name": "jeep", "dimensions": (3.4, 1.6, 1.8), "temperature": 302.0},
    ],
    background={"temperature": 295.0, "clutter_std": 2.0},
    atmosphere={"obscurant": "haze"},
    seed=7,
)
dt = 0.1  # [s]
mast = np.array([[0.0, 0.0, 10.0]])  # (sensors, 3): east, north, up [m]
start = np.array([[3000.0, 20.0, 0.0], [2000.0, -30.0, 0.0]])  # (targets, 3) [m]
velocity = np.array([[-40.0, 0.0, 0.0], [-25.0, 0.5, 0.0]])  # [m/s]

times, detection, recognition = [], [], []
for k in range(601):
    t = k * dt
    out = sim.step(t, dt, mast, start + velocity * t)
    times.append(t)
    detection.append(out.detection[0])
    recognition.append(out.recognition[0])
    for event in out.events:
        print(f"{event.time:6.2f} s  {event.sensor}: {event.task} of {event.target}")

# %%
# The probabilities the events were drawn from:

detection, recognition = np.array(detection), np.array(recognition)
fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
for j, name in enumerate(("truck", "jeep")):
    ax.plot(times, detection[:, j], label=f"detection — {name}")
    ax.plot(times, recognition[:, j], "--", label=f"recognition — {name}")
ax.set_xlabel("time [s]")
ax.set_ylabel("probability")
ax.set_ylim(0, 1)
ax.grid(True, alpha=0.3)
_ = ax.legend()
