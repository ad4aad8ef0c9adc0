"""Test configuration: Hypothesis without per-example deadlines (shared, noisy machines), and
with a fixed example sequence on CI so that a CI run is reproducible; locally the examples vary
from run to run and keep exploring."""

import os

from hypothesis import settings

settings.register_profile("default", deadline=None)
settings.register_profile("ci", deadline=None, derandomize=True, print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "default")
