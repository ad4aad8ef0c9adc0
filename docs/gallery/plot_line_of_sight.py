"""
Line of sight over terrain: a profile and a visibility map
==========================================================

An observer on a 5 m mast looks over synthetic hills (a 5 km square grid of 20 m posts). Left:
the terrain profile towards one target, the Earth's bulge with standard refraction added
(``d_o d_t / (2 k R_e)``, k = 4/3), and the highest sight line over it: the part of the target
above that line is what the observer sees (:func:`targetacq.line_of_sight`). Right: the visible
fraction of a 3 m target standing anywhere on the grid.
"""

import matplotlib.pyplot as plt
import numpy as np

import targetacq as ta
from targetacq.physics.line_of_sight import EARTH_RADIUS, STANDARD_K, ElevationModel

# Hills: a ridge running north-east and two rounded tops (row 0 is the southern edge).
spacing, side = 20.0, 256
x = np.arange(side) * spacing
east, north = np.meshgrid(x, x)
elevation = (
    22.0 * np.exp(-((((east - north) / np.sqrt(2) - 600.0) / 300.0) ** 2))
    + 30.0 * np.exp(-((east - 1200.0) ** 2 + (north - 3600.0) ** 2) / 500.0**2)
    + 45.0 * np.exp(-((east - 4000.0) ** 2 + (north - 1500.0) ** 2) / 700.0**2)
    + 3.0 * np.sin(east / 170.0) * np.cos(north / 230.0)
)
terrain = ElevationModel(elevation, spacing, (0.0, 0.0))
observer = np.array([800.0, 2000.0, 0.0])
observer[2] = float(terrain.height_at(observer[0], observer[1])) + 5.0
height = 3.0

# The visibility map: a 3 m target on the ground at every post.
grid_targets = np.stack([east, north, elevation], axis=-1)
fraction = ta.line_of_sight(terrain, None, None, observer, grid_targets, height)

# The profile's target: the farthest post where the target is partly hidden.
partial = np.argwhere((fraction > 0.3) & (fraction < 0.7))
far = partial[np.argmax(np.hypot(*(partial[:, ::-1] * spacing - observer[:2]).T))]
target = grid_targets[far[0], far[1]]
seen = ta.line_of_sight(terrain, None, None, observer, target, height)

# The profile: the terrain under the track, raised by the Earth bulge against the chord.
distance = float(np.hypot(*(target[:2] - observer[:2])))
d = np.linspace(0.0, distance, 400)
along = observer[:2] + np.outer(d / distance, target[:2] - observer[:2])
bulge = d * (distance - d) / (2 * STANDARD_K * EARTH_RADIUS)
ground = terrain.height_at(along[:, 0], along[:, 1]) + bulge
slope = np.max((ground[1:-1] - observer[2]) / d[1:-1])  # the highest sight line
line = observer[2] + slope * d

fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
left.fill_between(d / 1e3, ground.min() - 5.0, ground, color="0.8", label="terrain + bulge")
left.plot(d / 1e3, line, color="C3", lw=1.2, label="highest sight line")
left.plot([0.0], [observer[2]], "k^", label="observer (5 m mast)")
left.plot(
    [distance / 1e3] * 2,
    [target[2], target[2] + height],
    color="C0",
    lw=5,
    solid_capstyle="butt",
    label=f"3 m target: {float(seen):.0%} visible",
)
left.set_xlabel("distance from the observer [km]")
left.set_ylabel("altitude [m]")
left.legend(loc="upper right", fontsize=8)
left.set_title("profile towards the target")
image = right.imshow(
    fraction,
    origin="lower",  # row 0 south
    extent=(0.0, x[-1] / 1e3, 0.0, x[-1] / 1e3),
    cmap="viridis",
    vmin=0.0,
    vmax=1.0,
)
right.contour(east / 1e3, north / 1e3, elevation, levels=8, colors="w", linewidths=0.4)
right.plot(observer[0] / 1e3, observer[1] / 1e3, "r^")
right.plot(target[0] / 1e3, target[1] / 1e3, "wo", mfc="none")
right.set_xlabel("east [km]")
right.set_ylabel("north [km]")
right.set_title("visible fraction of a 3 m target")
fig.colorbar(image, ax=right, label="visible fraction")
