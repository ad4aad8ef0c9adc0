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
api_modules = [
    "targetacq",
    "targetacq.geometry",
    "targetacq.optics",
    "targetacq.radiometry",
    "targetacq.atmosphere",
    "targetacq.clutter",
    "targetacq.terrain",
    "targetacq.features",
    "targetacq.images",
    "targetacq.noise",
    "targetacq.sensor_noise",
    "targetacq.mrtd",
    "targetacq.transforms",
    "targetacq.observed_detection",
    "targetacq.criteria",
    "targetacq.acquisition",
    "targetacq.fusion",
    "targetacq.radar",
    "targetacq.laser_radar",
    "targetacq.false_targets",
    "targetacq.ranges",
    "targetacq.design",
    "targetacq.targets",
    "targetacq.scene",
    "targetacq.search",
    "targetacq.sampling",
    "targetacq.simulation",
    "targetacq.model",
    "targetacq.engines",
    "targetacq.streaming",
    "targetacq.web",
    "targetacq.envs",
    "targetacq.scenario",
    "targetacq.bundled",
    "targetacq.sensors",
    "targetacq.sensors.signature",
    "targetacq.sensors.imaging",
    "targetacq.sensors.thermal",
    "targetacq.sensors.tv",
    "targetacq.sensors.colour",
    "targetacq.sensors.swir",
    "targetacq.sensors.radar",
    "targetacq.sensors.laser_radar",
    "targetacq.core",
    "targetacq.core.records",
    "targetacq.core.cases",
    "targetacq.core.compile",
    "targetacq.core.evaluate",
    "targetacq.core.active",
    "targetacq.core.mrtd_rows",
    "targetacq.core.pair_ranges",
    "targetacq.bands",
    "targetacq.tables",
    "targetacq.units",
    "targetacq.limits",
    "targetacq.inputs",
    "targetacq.outputs",
    "targetacq.registry",
    "targetacq.constants",
    "targetacq.plots",
    "targetacq.report",
    "targetacq.report_content",
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
