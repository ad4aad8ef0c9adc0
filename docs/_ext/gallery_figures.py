"""A sphinx-gallery image scraper for matplotlib figures made without pyplot.

:mod:`targetacq.reports.plots` returns :class:`matplotlib.figure.Figure` objects that pyplot does
not manage (so a library call never opens a window), which the built-in scraper cannot see. This
scraper saves every such figure the example's code block has bound to a name, once; it must come
before the ``matplotlib`` scraper, which closes pyplot's figures.
"""

from __future__ import annotations

from pathlib import PurePosixPath
from typing import Any

__all__ = ["scrape"]

_SEEN: dict[str, set[int]] = {}


def scrape(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
    """Save the new unmanaged figures among the example's globals and return their reST."""
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    source = str(block_vars.get("src_file", ""))
    seen = _SEEN.setdefault(source, set())
    figures = []
    for value in block_vars["example_globals"].values():
        if not isinstance(value, Figure) or id(value) in seen:
            continue
        if value.canvas.manager is not None:  # pyplot's: the matplotlib scraper saves it
            seen.add(id(value))
        else:
            figures.append(value)
    paths = []
    for figure, path in zip(figures, block_vars["image_path_iterator"], strict=False):
        figure.savefig(path)
        seen.add(id(figure))
        paths.append(PurePosixPath(path))
    return figure_rst(paths, gallery_conf["src_dir"])
