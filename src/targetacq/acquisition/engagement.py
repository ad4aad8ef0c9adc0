"""What a sensor-target engagement keeps over time: the draw rules and the view crossings.

Draw rules (:data:`REDRAW_RULES`). The probabilities of the model are those of the observer
(sensor and interpreter) acquiring a target at a resolution: a property of the observer, the
target and the set-up, not of one glimpse. A target that leaves a sensor's field of view and
comes back is the same target seen by the same observer, so the uniform that decides whether
the observer *can* detect, recognise and identify it (the capability draw of
:mod:`targetacq.run.search`) is kept while the target is out of view, and drawn again only under a
stated rule:

``never`` (the default)
    One capability draw per sensor, target and run, from the first time the target is in view
    until :meth:`targetacq.Simulation.reset`. Whatever the pointing pattern and the step, the
    share of runs in which a task is ever done cannot exceed the largest probability of that
    task seen: looking away and back cannot raise it.
``after-out-of-view``
    A new draw when the target comes back after having been out of view for at least the
    model's ``decorrelation_time`` [s]: after that long the observer's state of mind, the
    lighting or the scene are taken as independent of the earlier look. The time is the user's
    (no published value exists for it; it is the project's rule, stated here). With a
    decorrelation time of 0 every glimpse is a new trial: the behaviour before this rule
    existed, which a pointing policy can exploit (looking away every other step raises the
    share identified several fold).

The search clock of detection (the exponential clock of :mod:`targetacq.run.search`) follows the
same rule, and between glimpses of one engagement the hazard accumulated so far is kept: the
time spent searching a target counts however it is split into glimpses. After a detection, a
target that leaves the view and comes back must be found again: a new clock for that search
(its events are "reacquired", :data:`targetacq.run.simulation.EVENT_KINDS`).

View crossings (:func:`view_crossings`). Within a step the sensors and targets move on straight
lines between their positions at the two ends and the boresight turns uniformly (normalised
linear interpolation of its directions at the two ends); the moment a target enters or leaves
the field of view is solved from that, to about 2e-5 of the step, so the time in view and the
first-detection times do not depend on the step size.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from targetacq.base.registry import lookup

__all__ = ["REDRAW_RULES", "RedrawRule", "get_redraw_rule", "view_crossings"]


@dataclass(frozen=True)
class RedrawRule:
    """A rule for drawing a pair's capability again (:data:`REDRAW_RULES`).

    Attributes
    ----------
    name : str
    uses_time : bool
        Whether the rule takes the model's ``decorrelation_time``.
    description : str
    source : str
    """

    name: str
    uses_time: bool
    description: str
    source: str

    def fresh(self, away: np.ndarray, decorrelation_time: float) -> np.ndarray:
        """Whether a target back in view after ``away`` seconds out of it gets new draws.

        ``away`` is +inf for a target never in view before (always new draws).
        """
        if self.uses_time:
            return away >= decorrelation_time
        return np.isinf(away)


REDRAW_RULES: Mapping[str, RedrawRule] = MappingProxyType(
    {
        "never": RedrawRule(
            "never",
            False,
            "one capability draw per sensor, target and run, kept while the target is out of "
            "view (until a reset)",
            "the project's reading of the model: P belongs to the observer and the target, not "
            "to a glimpse (see targetacq.acquisition.engagement)",
        ),
        "after-out-of-view": RedrawRule(
            "after-out-of-view",
            True,
            "new draws when the target comes back after at least decorrelation_time out of view",
            "the project's assumption; the decorrelation time is the user's",
        ),
    }
)
"""Rules for drawing a sensor-target pair's capability and search clock again (read-only)."""


def get_redraw_rule(name: str | RedrawRule) -> RedrawRule:
    """A rule of :data:`REDRAW_RULES` by name (``ValueError`` listing them otherwise).

    Examples
    --------
    >>> get_redraw_rule("never").uses_time
    False
    """
    return name if isinstance(name, RedrawRule) else lookup(REDRAW_RULES, name, "redraw rule")


# view_crossings samples the step at 33 points, then the bracket found at 33 points, three times:
# a bracket of 32⁻³ of the step, whose middle is within 1.6e-5 of the step of the crossing.
_SAMPLES = 33
_PASSES = 3


def _inside(
    s: np.ndarray,
    ends: tuple[np.ndarray, ...],
    half: tuple[np.ndarray, np.ndarray],
) -> np.ndarray:
    """In view at fractions ``s`` (m, k) of the step: the line of sight and the boresight at
    ``s``, the test of :func:`targetacq.physics.geometry.within_field_of_view` without normalising
    (each side multiplied by the positive norms it would divide by)."""
    los0, dlos, f0, df = ends
    sx, sy, sz = (los0[:, j, None] + s * dlos[:, j, None] for j in range(3))
    fx, fy, fz = (f0[:, j, None] + s * df[:, j, None] for j in range(3))
    ahead = sx * fx + sy * fy + sz * fz  # |f| · ahead
    flat = np.sqrt(fx * fx + fy * fy)  # |f_xy|
    norm = np.sqrt(fx * fx + fy * fy + fz * fz)
    right = sx * fy - sy * fx  # |f_xy| · right
    up = (sz * (fx * fx + fy * fy) - fz * (sx * fx + sy * fy)) / np.where(norm > 0, norm, 1.0)
    tan_h, tan_v = half[0][:, None], half[1][:, None]
    level = flat > 1e-12 * norm
    # Straight up or down (no horizontal boresight): the frame of targetacq.physics.geometry takes
    # east as right and north as up there.
    right = np.where(level, right, sx * norm)
    up = np.where(level, up, sy * norm)
    scale = np.where(level, flat, norm)
    return (
        (ahead > 0)
        & (np.abs(right) <= tan_h * ahead * scale / np.where(norm > 0, norm, 1.0))
        & (np.abs(up) <= tan_v * ahead * scale / np.where(norm > 0, norm, 1.0))
    )


def view_crossings(
    line_of_sight: tuple[np.ndarray, np.ndarray],
    boresight: tuple[np.ndarray, np.ndarray],
    half_tangents: tuple[np.ndarray, np.ndarray],
    entering: np.ndarray,
) -> np.ndarray:
    """When, within a step, targets enter or leave sensors' fields of view.

    The line of sight moves linearly from its value at the start of the step to its value at
    the end; the boresight turns by normalised linear interpolation. For a target entering
    (out of view at the start, in view at the end) the answer is the last moment it comes in;
    for one leaving, the first moment it goes out: the boundary of the part of the step next to
    the end at which it is in view.

    Parameters
    ----------
    line_of_sight : (array (m, 3), array (m, 3))
        Target minus sensor position at the start and at the end of the step [m].
    boresight : (array (m, 3), array (m, 3))
        The sensors' boresight directions (any length) at the start and at the end.
    half_tangents : (array (m,), array (m,))
        tan(FOV_h / 2), tan(FOV_v / 2) of each pair's sensor.
    entering : array of bool (m,)
        True where the target enters, False where it leaves.

    Returns
    -------
    numpy.ndarray (m,)
        The crossing as a fraction of the step in [0, 1]; 0.5 where no change of view is found
        between the two ends (a boresight that turns by 180°, or a test that disagrees with the
        ends' own at the ends).

    Examples
    --------
    A target 1000 m east crossing northward through a sensor's ±0.1 rad view looking east:
    from 150 m south to 50 m north it comes in at 0.1 · 1000 m = 100 m south, a
    quarter of the way.

    >>> import numpy as np
    >>> los = (np.array([[1000.0, -150.0, 0.0]]), np.array([[1000.0, 50.0, 0.0]]))
    >>> east = np.array([[1.0, 0.0, 0.0]])
    >>> s = view_crossings(los, (east, east), (np.array([0.1]), np.array([0.1])), np.array([True]))
    >>> round(float(s[0]), 4)
    0.25
    """
    los0 = np.asarray(line_of_sight[0], dtype=float)
    los1 = np.asarray(line_of_sight[1], dtype=float)
    f0 = np.asarray(boresight[0], dtype=float)
    f1 = np.asarray(boresight[1], dtype=float)
    # Unit boresights, so that the interpolation turns them evenly whatever their lengths.
    f0 = f0 / np.linalg.norm(f0, axis=1, keepdims=True)
    f1 = f1 / np.linalg.norm(f1, axis=1, keepdims=True)
    ends = (los0, los1 - los0, f0, f1 - f0)
    half = (np.asarray(half_tangents[0], dtype=float), np.asarray(half_tangents[1], dtype=float))
    entering = np.asarray(entering, dtype=bool)
    m = entering.size
    lo, width = np.zeros(m), np.ones(m)
    grid = np.linspace(0.0, 1.0, _SAMPLES)
    found = np.ones(m, dtype=bool)
    for n in range(_PASSES):
        inside = _inside(lo[:, None] + width[:, None] * grid, ends, half)
        out = ~inside
        if n == 0:  # the test must agree with the ends: out then in, or in then out
            found = (out[:, 0] == entering) & (inside[:, -1] == entering)
        # The boundary next to the end in view: entering, the last sample out of view;
        # leaving, the sample before the first one out.
        last_out = _SAMPLES - 1 - np.argmax(out[:, ::-1], axis=1)
        first_out = np.argmax(out, axis=1)
        k = np.clip(np.where(entering, last_out, first_out - 1), 0, _SAMPLES - 2)
        width = width / (_SAMPLES - 1)
        lo = lo + k * width
    return np.where(found, np.clip(lo + 0.5 * width, 0.0, 1.0), 0.5)
