"""`validate` and `evaluate` agree: whatever `validate` accepts, `evaluate` runs.

Hypothesis mutates the bundled examples, the golden scenarios (image, terrain, features) and two
small generated ones: it sets keys to valid and invalid values (quantities in and out of their
domain, overflowing numbers, quoted numbers, flags, unknown names), adds optional keys and
removes keys. Each mutated scenario is validated as ``targetacq validate`` does (the schema,
then :func:`targetacq.core.compile.check_runnable`); one it accepts must then evaluate, over the
first times of its grid, without an exception or a warning (the suite runs under ``-W error``),
with every probability in [0, 1] and NaN only where a terrain map gives no clutter measure
(a target off the map).
"""

import copy
import tomllib
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from targetacq.core.compile import check_runnable
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.plausibility import collected
from targetacq.scenario.schema import ScenarioError, parse_scenario

EXAMPLES = Path(__file__).parents[2] / "examples"
GOLDEN = Path(__file__).parents[1] / "data" / "golden"

SMALL_THERMAL = {
    "sensors": [
        {"name": "a", "band": "lwir", "ifov": "0.2 mrad", "position": ["0 m", "0 m", "5 m"]}
    ],
    "targets": [
        {
            "name": "t",
            "dimensions": ["2 m", "2 m", "2 m"],
            "temperature": "300 K",
            "position": ["1 km", "0 m", "0 m"],
        }
    ],
    "background": {"temperature": "290 K"},
    "time": {"stop": "4 s", "step": "1 s"},
}

SMALL_TV = {
    "sensors": [
        {
            "name": "cam",
            "type": "tv",
            "pixels": [1920, 1080],
            "hfov": "20 deg",
            "position": ["0 m", "0 m", "10 m"],
            "look_at": ["2 km", "0 m", "0 m"],
        }
    ],
    "targets": [
        {
            "name": "car",
            "dimensions": ["4 m", "2 m", "1.5 m"],
            "reflectance": 0.3,
            "waypoints": [
                {"time": "0 s", "position": ["3 km", "-200 m", "0 m"]},
                {"time": "10 s", "position": ["1 km", "200 m", "0 m"]},
            ],
        }
    ],
    "background": {"reflectance": 0.1, "irradiance": "500 W/m^2", "clutter": "low"},
    "time": {"stop": "10 s", "step": "2 s"},
}


def _read(path):
    data = tomllib.loads(path.read_text())
    background = data.get("background", {})
    if "image" in background:  # relative to the file, as load_scenario resolves them
        background["image"] = str((path.parent / background["image"]).resolve())
    if "terrain" in background:
        background["terrain"]["map"] = str(path.parent / background["terrain"]["map"])
    return data


BASES = [
    *(_read(path) for path in sorted(EXAMPLES.glob("*.toml"))),
    *(_read(path) for path in sorted(GOLDEN.glob("*.toml"))),
    SMALL_THERMAL,
    SMALL_TV,
]

LENGTHS = ["1 m", "0 m", "-2 m", "3 km", "1e-9 m", "1e7 m", "17 um", "1e400 m", 5, "5 K"]
ANGLES = ["0 deg", "45 deg", "-14 deg", "90 deg", "-90 deg", "720 deg", "1e-6 rad", "179 deg"]
TEMPERATURES = ["300 K", "0 K", "-5 K", "1e4 K", "1e5 K", "20 degC", "3 K", 300]
SPREADS = ["0 K", "50 mK", "2 K", "-1 K", "1e6 K", "1e4 K"]
TIMES = ["0 s", "1 s", "-1 s", "1e-3 s", "30 s", "1e9 s", "1e400 s"]
NUMBERS = [0, 1, 0.5, -1, 2, 1e308, 1e-308, 3.0, True, "0.5", 0.02]
POSITIONS = [
    ["0 m", "0 m", "0 m"],
    ["1 km", "0 m", "10 m"],
    ["0 m", "0 m", "10 m"],
    ["0 m", "0 m", "5 m"],
    "1 2 3 km",
    ["1 m", "1 m"],
    ["1e7 m", "0 m", "0 m"],
]
CHOICES = [
    "low",
    "medium",
    "high",
    "ttpf",
    "c2nveo",
    "schmieder-weathersby",
    "johnson",
    "johnson-jeep",
    "en62676-4",
    "haze",
    "haze:high",
    "rain",
    "vegetation",
    "olive-paint",
    "lwir",
    "mwir",
    "visible",
    "8-12 um",
    "tv",
    "thermal",
    "koschmieder",
    "mor",
    "luminance",
    "pessimistic",
    "nested",
    "conditional",
    "always",
    "none",
    "",
    "xyz",
]

POOLS = {
    **dict.fromkeys(
        ["pitch", "focal_length", "aperture", "length", "radius", "visibility", "resolution"],
        LENGTHS,
    ),
    "cell_size": ["1 km", "10 m", "0 m", "-1 m"],
    "dimensions": [["1 m", "1 m", "1 m"], ["0.1 m", "7 m", "3 m"], ["0 m", "1 m", "1 m"]],
    **dict.fromkeys(["hfov", "ifov", "azimuth", "depression", "heading"], ANGLES),
    **dict.fromkeys(["temperature", "netd_temperature"], TEMPERATURES),
    **dict.fromkeys(["netd", "clutter_std", "temperature_std"], SPREADS),
    **dict.fromkeys(["time", "start", "stop", "step", "search_time"], TIMES),
    "extinction": ["0 /km", "0.4 /km", "1e3 /km", "-1 /km", "3 dB/km", "1e400 /km"],
    "irradiance": ["500 W/m^2", "0 W/m^2", "-1 W/m^2", "1e30 W/m^2"],
    **dict.fromkeys(
        ["emissivity", "reflectance", "visible_fraction", "scr", "f_number", "nec"], NUMBERS
    ),
    "pixels": [[640, 512], [1, 1], [0, 5], [100, 4000], ["640", 1], [64.5, 2]],
    "image_box": [[0, 0, 4, 4], [412, 118, 20, 20], [500, 500, 20, 20], [0, 0, 0, 4]],
    **dict.fromkeys(["position", "look_at", "center"], POSITIONS),
    **{key: [True, False, "yes", 1] for key in ("moving", "hot_spot")},
    "n50": [[1, 4, 6.4], [8, 4, 1], [0.1, 0.1, 0.1], [1e300, 1e300, 1e300], [1, 4]],
    "segments": [[{"length": "100 m", "extinction": "5 /km"}], [{"length": "-1 m"}]],
    "clouds": [[{"center": ["500 m", "0 m", "2 m"], "radius": "20 m", "extinction": "30 /km"}]],
}

OPTIONAL = {
    "sensors": ["netd", "nec", "f_number", "aperture", "look_at", "azimuth", "depression"],
    "targets": ["hot_spot", "moving", "visible_fraction", "criterion", "material", "emissivity"],
    "background": ["clutter", "scr", "clutter_std", "material", "emissivity", "channel"],
    "atmosphere": ["extinction", "obscurant", "visibility", "visibility_convention", "segments"],
    "model": ["transform", "criterion", "n50", "bound", "noise_model", "motion", "semantics"],
    "time": ["start", "stop", "step"],
}


def _leaves(data, path=()):
    """Paths to every key of the nested tables (lists of tables by index)."""
    out = []
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in items:
        here = (*path, key)
        if isinstance(value, dict) or (
            isinstance(value, list) and value and isinstance(value[0], dict)
        ):
            out += _leaves(value, here)
        if isinstance(key, str):
            out.append(here)
    return out


def _at(data, path):
    for key in path:
        data = data[key]
    return data


@st.composite
def scenarios(draw):
    data = copy.deepcopy(draw(st.sampled_from(BASES)))
    for _ in range(draw(st.integers(1, 4))):
        action = draw(st.sampled_from(["set", "set", "add", "remove"]))
        if action == "add":
            table = draw(st.sampled_from(sorted(OPTIONAL)))
            where = data.setdefault(table, [] if table in ("sensors", "targets") else {})
            if isinstance(where, list) and where:
                where = where[draw(st.integers(0, len(where) - 1))]
            if not isinstance(where, dict):  # set to something else by an earlier mutation
                continue
            key = draw(st.sampled_from(OPTIONAL[table]))
            where[key] = copy.deepcopy(draw(st.sampled_from(POOLS.get(key, CHOICES))))
            continue
        path = draw(st.sampled_from(_leaves(data)))
        parent = _at(data, path[:-1])
        if action == "remove":
            del parent[path[-1]]
        else:
            parent[path[-1]] = copy.deepcopy(draw(st.sampled_from(POOLS.get(path[-1], CHOICES))))
    return data


def _accepted(data):
    """The scenario if ``targetacq validate`` accepts it, else None."""
    try:
        # The mutations reach implausible values on purpose (a visibility of 1 m): their
        # plausibility warnings are gathered, not raised, as validate prints and goes on.
        with collected():
            scenario = parse_scenario(data)
    except ScenarioError:
        return None
    return None if check_runnable(scenario) else scenario


@settings(
    max_examples=200,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(scenarios())
def test_what_validate_accepts_evaluate_runs(data):
    scenario = _accepted(data)
    if scenario is None:
        return
    grid = scenario.time
    times = grid.start + grid.step * np.arange(min(grid.count, 3.0))
    ds = ModelChain(scenario).evaluate(times).dataset
    undefined = np.isnan(ds["scr"].values)  # (sensor, target) or, from a map, (..., time)
    if undefined.ndim == 2:
        undefined = undefined[..., None]
    for task in ("detection", "recognition", "identification"):
        for name in (task, f"fused_{task}"):
            p = ds[name].values
            known = ~np.isnan(p)
            assert np.all((p[known] >= 0.0) & (p[known] <= 1.0)), name
            if name == task:  # NaN only where the terrain map gives no SCR (off the map)
                assert not np.any(~known & ~np.broadcast_to(undefined, p.shape)), name
            else:
                assert not np.any(~known & ~np.all(undefined, axis=0)), name


def test_the_bases_are_valid_and_run():
    for data in BASES:
        scenario = _accepted(copy.deepcopy(data))
        assert scenario is not None
