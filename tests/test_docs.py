"""The documentation: nothing points outside the repository; the registry tables are complete."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# Spelled in pieces, so that this file does not match itself.
FORBIDDEN = ("../" + "sha" + "red/", "MODEL" + ".md", "DESIGN" + ".md")


def _tracked_files() -> list[Path]:
    try:
        listing = subprocess.run(
            ["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return [ROOT / name for name in listing.decode().split("\0") if name]


def test_no_tracked_file_points_outside_the_repository() -> None:
    hits = []
    for path in _tracked_files():
        if not path.is_file():  # deleted in the working tree, not yet committed
            continue
        data = path.read_bytes()
        if b"\0" in data:  # binary
            continue
        text = data.decode("utf-8", errors="replace")
        for number, line in enumerate(text.splitlines(), 1):
            if any(word in line for word in FORBIDDEN):
                hits.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}")
    assert not hits, "references outside the repository:\n" + "\n".join(hits)


@pytest.fixture(scope="module")
def registry_tables():  # the docs' Sphinx extension, docs/_ext/registry_tables.py
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        import registry_tables
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    return registry_tables


def test_every_registry_entry_is_a_row(registry_tables) -> None:
    from targetacq.acquisition import ACQUISITION_SEMANTICS, MOTION_RULES
    from targetacq.atmosphere import EXTINCTION_LEVELS, OBSCURANTS, VISIBILITY_CONVENTIONS
    from targetacq.bands import BANDS
    from targetacq.criteria import CRITERIA
    from targetacq.engagement import REDRAW_RULES
    from targetacq.noise import NOISE_MODELS
    from targetacq.optics import FIELD_OF_VIEW_PROJECTIONS
    from targetacq.plausibility import PLAUSIBLE_RANGES
    from targetacq.sensors import SENSOR_TYPES
    from targetacq.targets import TARGETS
    from targetacq.transforms import CLUTTER_REGIONS, TRANSFORMS

    expected = {
        "targetacq.criteria.CRITERIA": CRITERIA,
        "targetacq.transforms.TRANSFORMS": TRANSFORMS,
        "targetacq.noise.NOISE_MODELS": NOISE_MODELS,
        "targetacq.sensors.SENSOR_TYPES": SENSOR_TYPES,
        "targetacq.targets.TARGETS": TARGETS,
        "targetacq.bands.BANDS": BANDS,
        "targetacq.atmosphere.OBSCURANTS": OBSCURANTS,
        "targetacq.atmosphere.EXTINCTION_LEVELS": EXTINCTION_LEVELS,
        "targetacq.atmosphere.VISIBILITY_CONVENTIONS": VISIBILITY_CONVENTIONS,
        "targetacq.transforms.CLUTTER_REGIONS": CLUTTER_REGIONS,
        "targetacq.acquisition.MOTION_RULES": MOTION_RULES,
        "targetacq.acquisition.ACQUISITION_SEMANTICS": ACQUISITION_SEMANTICS,
        "targetacq.optics.FIELD_OF_VIEW_PROJECTIONS": FIELD_OF_VIEW_PROJECTIONS,
        "targetacq.engagement.REDRAW_RULES": REDRAW_RULES,
        # A table of records: each row is named by where its quantity is in a scenario.
        "targetacq.plausibility.PLAUSIBLE_RANGES": [
            ", ".join(row.locations) for row in PLAUSIBLE_RANGES
        ],
    }
    tables = {table.origin: table for table in registry_tables.registries()}
    assert set(tables) == set(expected)
    for origin, registry in expected.items():
        table = tables[origin]
        assert [row[0] for row in table.rows] == list(registry), origin
        assert all(len(row) == len(table.header) for row in table.rows), origin
        assert all(all(cell.strip() for cell in row) for row in table.rows), origin
        text = registry_tables.render(table)
        assert text.count("\n   * - ") == len(registry) + 1, origin  # the header and one per entry
        for name in registry:
            assert f"``{name}``" in text, (origin, name)
