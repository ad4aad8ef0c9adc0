"""Sphinx configuration of the targetacq documentation (``make docs``).

Offline by design: no intersphinx, no downloaded theme, math as MathML, no remote script (the
``offline`` extension checks the built site); warnings are errors (``-W``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import targetacq

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

project = "targetacq"
author = "the targetacq authors"
copyright = "the targetacq authors"
version = release = targetacq.__version__

extensions = [
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "registry_tables",
    "cli_reference",
    "offline",
]

# Math is written as MathML (docs/_ext/offline.py): the browser draws it, nothing is downloaded,
# and the build fails if a page would load anything from another host.
html_math_renderer = "mathml"
exclude_patterns = ["_build", "_ext", "gallery", "**.ipynb", "**.zip", "**.py.md5"]
templates_path: list[str] = []
source_suffix = {".rst": "restructuredtext"}
root_doc = "index"
language = "en"
today_fmt = "%Y"

html_theme = "alabaster"
html_title = f"targetacq {release}"
html_static_path: list[str] = []
html_theme_options = {
    "description": "Probabilities of detection, recognition and identification",
    "fixed_sidebar": False,
    "page_width": "1100px",
    "sidebar_width": "230px",
}
html_show_sourcelink = False

# autodoc: members in source order, no values of the registries (their reprs are long).
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_default_options = {"members": True, "no-value": True}
autoclass_content = "class"

# numpydoc: no class member tables (autodoc lists them), no validation checks.
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = False
numpydoc_xref_param_type = False

# One API page per module (written by the registry_tables extension into generated/api).
api_modules = [  # by layer, lowest first (the contributor page "Architecture")
    "targetacq",
    "targetacq.base.sampling",
    "targetacq.base.bundled",
    "targetacq.base.tables",
    "targetacq.base.units",
    "targetacq.base.limits",
    "targetacq.base.inputs",
    "targetacq.base.registry",
    "targetacq.base.constants",
    "targetacq.io.images",
    "targetacq.io.files",
    "targetacq.io.html_report",
    "targetacq.acquisition.path_noise",
    "targetacq.acquisition.transforms",
    "targetacq.acquisition.observed_detection",
    "targetacq.acquisition.criteria",
    "targetacq.acquisition.calibration",
    "targetacq.acquisition.probabilities",
    "targetacq.acquisition.fusion",
    "targetacq.physics.geometry",
    "targetacq.physics.optics",
    "targetacq.physics.radiometry",
    "targetacq.physics.atmosphere",
    "targetacq.physics.clutter",
    "targetacq.physics.terrain",
    "targetacq.physics.line_of_sight",
    "targetacq.physics.features",
    "targetacq.physics.detector_noise",
    "targetacq.physics.mtf",
    "targetacq.physics.mrtd",
    "targetacq.physics.ttp",
    "targetacq.physics.radar_equation",
    "targetacq.physics.laser_radar_equation",
    "targetacq.physics.targets",
    "targetacq.physics.bands",
    "targetacq.sensors",
    "targetacq.sensors.signature",
    "targetacq.sensors.imaging",
    "targetacq.sensors.thermal",
    "targetacq.sensors.tv",
    "targetacq.sensors.colour",
    "targetacq.sensors.swir",
    "targetacq.sensors.radar",
    "targetacq.sensors.laser_radar",
    "targetacq.scenario.schema",
    "targetacq.core.ranges",
    "targetacq.core.engines",
    "targetacq.core",
    "targetacq.core.records",
    "targetacq.core.cases",
    "targetacq.core.compile",
    "targetacq.core.evaluation",
    "targetacq.core.pair_factors",
    "targetacq.core.active",
    "targetacq.core.mrtd_rows",
    "targetacq.core.pair_ranges",
    "targetacq.run.false_targets",
    "targetacq.run.design",
    "targetacq.run.scene",
    "targetacq.run.search",
    "targetacq.run.simulation",
    "targetacq.run.model_chain",
    "targetacq.run.streaming",
    "targetacq.reports.plots",
    "targetacq.reports.content",
    "targetacq.web",
    "targetacq.envs",
]

sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "image_scrapers": ("gallery_figures.scrape", "matplotlib"),
    "reset_modules": ("matplotlib",),
    "show_memory": False,
    "write_computation_times": False,
}
