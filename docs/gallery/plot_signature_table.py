"""
A signature over the aspect
===========================

A tank whose engine deck and exhaust are warmer than its front, engine running or not, on a
background of 295 K with a 2 K clutter spread, seen by a 50 mK thermal camera 3 km away
(:mod:`targetacq.physics.aspect`). Left: the table (temperature over the observer's azimuth
from the tank's heading, at 10° elevation). Right: the camera's probability of detection as
the tank turns, with each state's table and with one temperature (the engine-on table's mean):
the one number over-rates the front and under-rates the rear.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from targetacq import Simulation, core

AZIMUTHS = [0, 45, 90, 135, 180, 225, 270, 315]
STATES = {  # temperature [K] at each azimuth, 0 and 30 deg elevation (illustrative)
    "engine on": ([296.0, 297.0, 299.0, 303.0, 308.0, 303.0, 299.0, 297.0], 1.0),
    "engine off": ([295.4, 295.6, 296.0, 296.3, 296.6, 296.3, 296.0, 295.6], 0.5),
}


def table(values, deck):
    """A written signature table: the deck adds ``deck`` K seen from 30 deg up."""
    return {
        "azimuth": [f"{a} deg" for a in AZIMUTHS],
        "elevation": ["0 deg", "30 deg"],
        "temperature": [[f"{t} K", f"{t + deck} K"] for t in values],
    }


def detection(signature, headings):
    """P(detection) of the tank 3 km north of the camera, 10 deg below it, by heading."""
    tank = {"name": "tank", "dimensions": (7.0, 3.5, 2.5), **signature}
    camera = {"name": "ir", "band": "lwir", "ifov": 0.25e-3, "netd": 0.05}
    sim = Simulation([camera], [tank], background={"temperature": 295.0, "clutter_std": 2.0})
    up = 3000.0 * math.tan(math.radians(10.0))
    sensors = np.array([[[0.0, 3000.0, up]] * headings.size]).reshape(1, -1, 3)
    targets = np.zeros((1, headings.size, 3))
    _, p = core.evaluate(sim.compiled.scene, sensors, targets, headings[None])
    return p.detection[0, 0]


headings = np.radians(np.arange(0.0, 361.0, 5.0))
observer = np.remainder(-headings, 2 * math.pi)  # the camera's azimuth in the tank's frame
fig = plt.figure(figsize=(10, 4.2))
left = fig.add_subplot(1, 2, 1, projection="polar")
right = fig.add_subplot(1, 2, 2)
mean = float(np.mean([t + d for t in STATES["engine on"][0] for d in (0.0, 1.0)]))
p_one = detection({"temperature": mean}, headings)
right.plot(np.degrees(observer), p_one, "-", color="0.5", label=f"one temperature, {mean:.1f} K")
for (state, (values, deck)), colour in zip(STATES.items(), ("C3", "C0"), strict=True):
    closed = np.radians(AZIMUTHS + [360])
    left.plot(closed, values + values[:1], "o-", color=colour, label=state)
    p = detection({"signature_table": table(values, deck)}, headings)
    right.plot(np.degrees(observer), p, ".", color=colour, label=f"{state}: table")
left.set_theta_zero_location("N")
left.set_theta_direction(-1)
left.set_rlim(294.0, 309.0)
left.set_rticks([296, 300, 304, 308])
left.set_title("temperature [K] by the observer's azimuth\n(0 = head-on, 90 = right side)")
left.legend(loc="lower left", fontsize=8)
right.set_xlabel("observer's azimuth from the tank's heading [deg]")
right.set_ylabel("P(detection)")
right.set_xticks(range(0, 361, 45))
right.set_ylim(0.0, 1.0)
right.grid(alpha=0.3)
right.legend(fontsize=8)
fig.tight_layout()
plt.show()
