"""Plausibility warnings: valid values that no real sensor or scene has, most often a unit slip.

A scenario takes SI numbers from Python (``focal_length=0.1``) and quantities with units from
files (``focal_length = "100 mm"``). A number meant in another unit is still a valid length:
``focal_length=100`` (meant in mm) is a 100 m lens, every target is identified, and nothing
says why. :data:`PLAUSIBLE_RANGES` is the one table of such slips: per quantity, where it is in
the scenario schema, its SI unit, the limit that no real sensor or scene reaches and why, and
the slip it most likely is. :func:`plausibility_warnings` lists the values of a scenario beyond
those limits, each located and with its likely fix::

    sensors[0].focal_length: 100 m is 5 m or more; was it given in mm? (give "100 mm" or 0.1)

These are warnings, not errors: the scenario stays valid and runs as given. Validating a
:class:`targetacq.scenario.schema.Scenario` emits each one as a :class:`PlausibilityWarning` (a
``UserWarning``), so the step API (:class:`targetacq.Simulation`), scenario files and the
environments warn alike; the command line prints each as one line on stderr, and the web API
answers them in a ``"warnings"`` list. :func:`collected` gathers them instead of emitting them
(for a server, where warnings must not go to a shared stream).

Examples
--------
>>> from targetacq.scenario.plausibility import collected, plausibility_warnings
>>> from targetacq.scenario.schema import Scenario
>>> with collected():  # gathered here rather than emitted
...     scenario = Scenario.model_validate({
...         "sensors": [{"name": "ir", "band": "lwir", "pitch": 17e-6, "focal_length": 100,
...                      "position": (0, 0, 10)}],
...         "targets": [{"name": "truck", "dimensions": (7, 2.5, 3), "temperature": 305,
...                      "position": (2000, 0, 0)}],
...         "background": {"temperature": 295}})
>>> plausibility_warnings(scenario)
['sensors[0].focal_length: 100 m is 5 m or more; was it given in mm? (give "100 mm" or 0.1)']
"""

from __future__ import annotations

import contextvars
import re
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Literal

from targetacq.base.units import parse_quantity

__all__ = [
    "PLAUSIBLE_RANGES",
    "PlausibilityWarning",
    "PlausibleRange",
    "collected",
    "emit",
    "plausibility_warnings",
]


class PlausibilityWarning(UserWarning):
    """A scenario value that is valid but beyond what any real sensor or scene has (most often
    a unit slip); the message says where, the limit, and the likely fix."""


@dataclass(frozen=True)
class PlausibleRange:
    """One quantity's plausible range and the slip a value beyond it most likely is.

    Attributes
    ----------
    locations : tuple of str
        Where the quantity is in the scenario schema: ``sensors[].focal_length`` (``[]`` every
        item of a list, ``[2]`` one component, e.g. the up coordinate of a position).
    kind : str
        The quantity's kind (a key of :data:`targetacq.base.units.DIMENSIONS`).
    unit : str
        Its SI unit, in which values are shown.
    limit : str
        The limit, a quantity with its unit (``"5 m"``).
    side : {"above", "below"}
        Whether values at or above the limit warn, or values at or below it.
    question : str
        The likely slip, asked: ``"was it given in mm?"``.
    reason : str
        Why no real sensor or scene reaches the limit.
    meant : str or None
        The unit the number was most likely meant in, for the fix (None: no single fix).
    written : str or None
        The unit the number was most likely written in (None: the SI unit, a bare Python
        number).
    read : str or None
        Where the value is read when that differs from the location shown (a band's upper
        limit, ``sensors[].limits[1]``, shown as ``sensors[].band``); the same ``[]`` lists.
    unless : str or None
        A sibling field that, when given, makes this one derived and so not checked (an
        ``aperture`` computed from ``f_number``).
    number : bool
        Whether the fix can be given as an SI number from Python (not for a band's text).
    """

    locations: tuple[str, ...]
    kind: str
    unit: str
    limit: str
    side: Literal["above", "below"]
    question: str
    reason: str
    meant: str | None = None
    written: str | None = None
    read: str | None = None
    unless: str | None = None
    number: bool = True

    @property
    def threshold(self) -> float:
        """The limit in :attr:`unit` (SI)."""
        return parse_quantity(self.limit, self.kind, "limit")

    def beyond(self, value: float) -> bool:
        """Whether ``value`` [SI] is at or beyond the limit."""
        return value >= self.threshold if self.side == "above" else value <= self.threshold

    def message(self, where: str, value: float) -> str:
        """The warning for ``value`` [SI] at ``where``: the value, the limit, the slip, the fix."""
        text = (
            f"{where}: {value:g} {self.unit} is {self.limit} or "
            f"{'more' if self.side == 'above' else 'less'}; {self.question}"
        )
        if self.meant is None:
            return text
        written = self.written or self.unit
        given = value / parse_quantity(f"1 {written}", self.kind, where)
        fixed = f"{given:g} {self.meant}"
        if not self.number:
            return f'{text} (give "{fixed}")'
        si = parse_quantity(fixed, self.kind, where)
        return f'{text} (give "{fixed}" or {si:g})'


_POSITIONS = (
    "sensors[].position[2]",
    "sensors[].waypoints[].position[2]",
    "sensors[].look_at[2]",
    "targets[].position[2]",
    "targets[].waypoints[].position[2]",
)

PLAUSIBLE_RANGES: tuple[PlausibleRange, ...] = (
    PlausibleRange(
        ("sensors[].focal_length",),
        "length",
        "m",
        "5 m",
        "above",
        "was it given in mm?",
        "the longest lenses of imaging sensors, long-range surveillance and tracking optics, "
        "are about 3 m; focal lengths in mm (8 mm and up) read as metres are over it",
        meant="mm",
    ),
    PlausibleRange(
        ("sensors[].pitch",),
        "length",
        "m",
        "1 mm",
        "above",
        "was it given in um?",
        "detector pixels are 1 to 50 um; a pitch in um read as metres (17 m) is over 1 mm, "
        "and so is one in mm read as metres (0.017 m)",
        meant="um",
    ),
    PlausibleRange(
        ("sensors[].aperture", "sensors[].laser.aperture"),
        "length",
        "m",
        "5 m",
        "above",
        "was it given in mm?",
        "the entrance pupils of imaging sensors are under 1 m; a diameter in mm read as metres "
        "is over 5 m from 5 mm up (an aperture computed from f_number is not checked here: its "
        "focal length is)",
        meant="mm",
        unless="f_number",
    ),
    PlausibleRange(
        ("sensors[].ifov",),
        "angle",
        "rad",
        "0.1 rad",
        "above",
        "was it given in mrad?",
        "0.1 rad (5.7 deg) per pixel is coarser than the coarsest thermal arrays (about 0.05 "
        "rad: 32 pixels over 90 deg); IFOVs in mrad (0.01 to 2) read as radians reach it from "
        "0.1 mrad",
        meant="mrad",
    ),
    PlausibleRange(
        ("sensors[].band",),
        "length",
        "m",
        "1 mm",
        "above",
        "were the band limits given in mm for um?",
        "imaging bands end in the far infrared, below 1 mm (the LWIR band ends at 14 um); a "
        "band written in mm for um (8-12 mm) is over it",
        meant="um",
        written="mm",
        read="sensors[].limits[1]",
        number=False,
    ),
    PlausibleRange(
        ("sensors[].netd",),
        "temperature difference",
        "K",
        "5 K",
        "above",
        "was it given in mK?",
        "thermal cameras have NETDs of 0.01 to 0.3 K (old or cheap arrays up to about 1 K); "
        "NETDs in mK (20 to 300) read as kelvin are over 5 K",
        meant="mK",
    ),
    PlausibleRange(
        (
            "targets[].temperature",
            "background.temperature",
            "background.terrain.classes[].temperature",
            "sensors[].netd_temperature",
            "targets[].temperature.mean",
            "background.temperature.mean",
            "background.terrain.classes[].temperature.mean",
        ),
        "temperature",
        "K",
        "150 K",
        "below",
        "was it given in degC?",
        "the coldest surfaces on Earth are about 180 K (-93 degC, the Antarctic plateau); "
        "temperatures in degC (up to 150) read as kelvin are under it",
        meant="degC",
    ),
    PlausibleRange(
        (
            "targets[].temperature",
            "background.temperature",
            "background.terrain.classes[].temperature",
            "sensors[].netd_temperature",
            "targets[].temperature.mean",
            "background.temperature.mean",
            "background.terrain.classes[].temperature.mean",
        ),
        "temperature",
        "K",
        "3000 K",
        "above",
        "was a digit typed too many (3050 K for 305.0 K)?",
        "the model's targets are boxes of one surface temperature; engine exhausts reach about "
        "1000 K and flares and rocket plumes 2000 to 3000 K (values in mK are refused "
        "already: over 10000 K)",
    ),
    PlausibleRange(
        ("background.clutter_std", "background.terrain.classes[].temperature_std"),
        "temperature difference",
        "K",
        "50 K",
        "above",
        "was it given in mK?",
        "natural backgrounds spread a few kelvin (tens between sunlit rock and shade); a "
        "spread in mK (1000 for 1 K) read as kelvin is over 50 K",
        meant="mK",
    ),
    PlausibleRange(
        _POSITIONS,
        "length",
        "m",
        "100 km",
        "above",
        "was it given in km for m?",
        "over 100 km up is space, above the atmosphere the model's paths assume; a height in m "
        "written with km (1500 km for 1500 m) is over it",
        meant="m",
        written="km",
    ),
    PlausibleRange(
        ("targets[].dimensions[0]",),
        "length",
        "m",
        "500 m",
        "above",
        "was it given in cm?",
        "the longest ship ever built was 458 m long; a vehicle's length in cm (700 for 7 m) "
        "read as metres is over 500 m",
        meant="cm",
    ),
    PlausibleRange(
        ("targets[].dimensions[1]", "targets[].dimensions[2]"),
        "length",
        "m",
        "100 m",
        "above",
        "was it given in cm?",
        "the widest ships are about 75 m across and 75 m tall above the water; a width or "
        "height in cm (250 for 2.5 m) read as metres is over 100 m",
        meant="cm",
    ),
    PlausibleRange(
        ("atmosphere.extinction", "atmosphere.segments[].extinction"),
        "extinction",
        "/m",
        "0.2 /m",
        "above",
        "was it given per km?",
        "0.2 /m is ten times Table 7.1's densest fog (20 /km), a visibility of 20 m; "
        "extinctions per km (0.2 to 20) read per metre are over it",
        meant="/km",
    ),
    PlausibleRange(
        ("atmosphere.clouds[].extinction",),
        "extinction",
        "/m",
        "10 /m",
        "above",
        "was it given per km?",
        "10 /m (a tenth of a metre of cloud dims by e) is 500 times Table 7.1's densest fog; a "
        "local cloud's extinction per km (10 and up) read per metre is over it",
        meant="/km",
    ),
    PlausibleRange(
        ("atmosphere.visibility",),
        "length",
        "m",
        "20 m",
        "below",
        "was it given in km?",
        "a visibility of 20 m is an extinction of 0.2 /m, ten times Table 7.1's densest fog; "
        "visibilities in km (20 and under) read as metres are under it",
        meant="km",
    ),
    PlausibleRange(
        ("atmosphere.rain_rate",),
        "speed",
        "m/s",
        "3600 mm/h",
        "above",
        "was it given in mm/h?",
        "the heaviest rain measured is about 300 mm/h (8e-5 m/s); a rate in mm/h read as m/s "
        "is over 1 mm/s (3600 mm/h) from 0.001 mm/h up",
        meant="mm/h",
    ),
    PlausibleRange(
        ("model.search_time",),
        "time",
        "s",
        "600 s",
        "above",
        "was it given in ms?",
        "search-time constants are seconds (3.4 s by default, tens of seconds for a wide field "
        "of regard); a constant in ms (3400 for 3.4 s) read as seconds is over 10 min",
        meant="ms",
    ),
    PlausibleRange(
        ("sensors[].radar.power",),
        "power",
        "W",
        "100 MW",
        "above",
        "was it given in MW for kW?",
        "the most powerful radars peak at 10 to 30 MW (Cobra Dane: 15.4 MW); a peak power in "
        "kW written with MW (250 MW for 250 kW) is over 100 MW",
        meant="kW",
        written="MW",
    ),
    PlausibleRange(
        ("sensors[].radar.frequency",),
        "frequency",
        "Hz",
        "1 MHz",
        "below",
        "was it given in GHz?",
        "radars run from 3 MHz (over-the-horizon) to about 100 GHz; a frequency in GHz read as "
        "hertz is under 1 MHz",
        meant="GHz",
    ),
    PlausibleRange(
        ("sensors[].radar.pulse_length",),
        "time",
        "s",
        "10 ms",
        "above",
        "was it given in us?",
        "radar pulses last 0.1 to a few hundred us (about 1 ms for the longest); a pulse length "
        "in us read as seconds is over 10 ms",
        meant="us",
    ),
    PlausibleRange(
        ("sensors[].laser.timing",),
        "time",
        "s",
        "1 ms",
        "above",
        "was it given in ns?",
        "a laser radar's timing resolution is 0.1 to 100 ns (range cells of 1.5 cm to 15 m); "
        "a timing in ns read as seconds is over 1 ms",
        meant="ns",
    ),
    PlausibleRange(
        ("false_targets.max_range",),
        "length",
        "m",
        "1000 km",
        "above",
        "was it given in km for m?",
        "the horizon from 20 km up is about 500 km away; a range in m written with km (5000 km "
        "for 5000 m) is over 1000 km",
        meant="m",
        written="km",
    ),
    PlausibleRange(
        ("false_targets.density",),
        "area density",
        "/m^2",
        "0.01 /m^2",
        "above",
        "was it given per km^2?",
        "one target-sized object per 100 m^2 (10000 /km^2) covers the ground; a density per "
        "km^2 read per m^2 is over it from 0.01 /km^2 up",
        meant="/km^2",
    ),
)
"""The plausible range of each quantity and its likely slip (the one table: the warnings, their
tests and the documentation's table are read from it)."""

_TOKEN = re.compile(r"^(\w+)(?:\[(\d*)\])?$")


def _walk(item: Any, parts: Sequence[str], index: tuple[int, ...]) -> Iterator[tuple[Any, ...]]:
    """(indices of the ``[]`` lists, value, the object holding the field) along ``parts``."""
    match = _TOKEN.match(parts[0])
    if match is None:  # a malformed location in the table: its test says which
        raise ValueError(f"cannot read location part {parts[0]!r}")
    name, position = match.groups()
    value = getattr(item, name, None)
    if value is None:
        return
    if position is None:
        values: list[tuple[tuple[int, ...], Any]] = [(index, value)]
    elif position == "":
        values = [((*index, k), v) for k, v in enumerate(value)]
    else:
        values = [(index, value[int(position)])]
    for where, found in values:
        if len(parts) == 1:
            yield where, found, item
        else:
            yield from _walk(found, parts[1:], where)


def _located(template: str, index: tuple[int, ...]) -> str:
    """``template`` with its ``[]`` filled by ``index`` in turn: ``sensors[0].focal_length``."""
    pieces = template.split("[]")
    return pieces[0] + "".join(f"[{k}]{piece}" for k, piece in zip(index, pieces[1:], strict=True))


def plausibility_warnings(scenario: Any) -> list[str]:
    """The values of a scenario beyond :data:`PLAUSIBLE_RANGES`, each a located message.

    Parameters
    ----------
    scenario : targetacq.scenario.schema.Scenario
        A validated scenario (SI values).

    Returns
    -------
    list of str
        One message per value, in the table's order: where, the value [SI], the limit, the
        likely slip and its fix, e.g. ``sensors[0].focal_length: 100 m is 5 m or more; was it
        given in mm? (give "100 mm" or 0.1)``. Empty for a plausible scenario.
    """
    found: list[str] = []
    for row in PLAUSIBLE_RANGES:
        for location in row.locations:
            read = row.read or location
            for index, value, holder in _walk(scenario, read.split("."), ()):
                if row.unless is not None and getattr(holder, row.unless, None) is not None:
                    continue
                if isinstance(value, (int, float)) and row.beyond(float(value)):
                    found.append(row.message(_located(location, index), float(value)))
    return found


_SINK: contextvars.ContextVar[list[str] | None] = contextvars.ContextVar(
    "targetacq_plausibility_sink", default=None
)


def emit(messages: Sequence[str], stacklevel: int = 2) -> None:
    """Emit each message as a :class:`PlausibilityWarning`, or add it to the list of the
    innermost :func:`collected` of this thread or task."""
    sink = _SINK.get()
    for message in messages:
        if sink is not None:
            sink.append(message)
        else:
            warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel + 1)


@contextmanager
def collected() -> Iterator[list[str]]:
    """Gather the plausibility warnings emitted inside, in a list, instead of emitting them.

    Safe in threads and tasks (a context variable, not the process-wide warning filters): a
    server gathers each request's warnings apart.

    Yields
    ------
    list of str
        Filled with the messages as they are emitted.

    Examples
    --------
    >>> from targetacq.scenario.plausibility import collected
    >>> from targetacq.scenario.schema import Scenario
    >>> with collected() as found:
    ...     _ = Scenario.model_validate({
    ...         "sensors": [{"name": "ir", "band": "lwir", "ifov": 0.25, "position": (0, 0, 10)}],
    ...         "targets": [{"name": "truck", "dimensions": (7, 2.5, 3), "temperature": 305,
    ...                      "position": (2000, 0, 0)}],
    ...         "background": {"temperature": 295}})
    >>> for part in found[0].split("; "):
    ...     print(part)
    sensors[0].ifov: 0.25 rad is 0.1 rad or more
    was it given in mrad? (give "0.25 mrad" or 0.00025)
    """
    sink: list[str] = []
    token = _SINK.set(sink)
    try:
        yield sink
    finally:
        _SINK.reset(token)
