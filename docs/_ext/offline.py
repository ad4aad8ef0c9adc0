"""The documentation works offline: math as MathML, and no page loads anything from the network.

- **Math** (``.. math::`` and ``:math:``) is converted to MathML when the pages are written
  (``latex2mathml``, pure Python, the ``docs`` extra), which browsers draw themselves: no
  MathJax, no script, no font to download. :func:`mathml` is the conversion; the HTML math
  renderer ``mathml`` (``html_math_renderer = "mathml"`` in ``conf.py``) uses it. A formula it
  cannot convert is a build warning (an error under ``-W``).
- **No remote resource**: when the build finishes, every HTML page and style sheet of the site
  is read, and each script, style sheet, image or frame it would load from another host
  (``http:``, ``https:`` or ``//``) is a build warning naming the page (:func:`remote_resources`).
  Links (``<a href>``) are not loaded by the browser and are not checked here.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

__all__ = ["mathml", "remote_resources", "setup"]

# Attributes through which a page makes the browser fetch something as it loads.
_LOADED = {
    "script": ("src",),
    "img": ("src", "srcset"),
    "iframe": ("src",),
    "embed": ("src",),
    "object": ("data",),
    "source": ("src", "srcset"),
    "audio": ("src",),
    "video": ("src", "poster"),
    "track": ("src",),
    "input": ("src",),
}
_LINK_RELS = {"stylesheet", "preload", "modulepreload", "icon", "shortcut", "prefetch", "manifest"}
_REMOTE = re.compile(r"^\s*(?:[a-z][a-z0-9+.-]*:)?//", re.IGNORECASE)
_CSS_URL = re.compile(r"""(?:url\(\s*['"]?|@import\s+['"])([^'")\s]+)""", re.IGNORECASE)


def mathml(latex: str, *, display: bool) -> str:
    """LaTeX math as a MathML ``<math>`` element (``display="block"`` for displayed math).

    Examples
    --------
    >>> print(mathml("x^2", display=False).replace("><", ">\\n<"))
    <math xmlns="http://www.w3.org/1998/Math/MathML" display="inline">
    <mrow>
    <msup>
    <mi>x</mi>
    <mn>2</mn>
    </msup>
    </mrow>
    </math>
    """
    from latex2mathml.converter import convert

    return str(convert(latex, display="block" if display else "inline"))


class _Resources(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.found: list[tuple[int, str, str]] = []  # (line, tag, url)

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = {name: value or "" for name, value in attrs}
        names = _LOADED.get(tag, ())
        if tag == "link" and _LINK_RELS & set(values.get("rel", "").lower().split()):
            names = ("href",)
        for name in names:
            value = values.get(name, "")
            # A srcset is a list: "url descriptor, url descriptor".
            if "set" in name:
                urls = [c.split()[0] for c in value.split(",") if c.split()]
            else:
                urls = [value]
            self.found += [(self.getpos()[0], tag, url) for url in urls if _REMOTE.match(url)]
        if tag == "style" or "style" in values:
            for url in _CSS_URL.findall(values.get("style", "")):
                if _REMOTE.match(url):
                    self.found.append((self.getpos()[0], tag, url))

    def handle_data(self, data: str) -> None:
        if self.lasttag == "style":
            for url in _CSS_URL.findall(data):
                if _REMOTE.match(url):
                    self.found.append((self.getpos()[0], "style", url))


def remote_resources(site: Path) -> list[str]:
    """Every resource that a page or style sheet under ``site`` loads from another host.

    One line each: ``path:line: <tag> url`` (path relative to ``site``), in file order.

    Examples
    --------
    >>> import tempfile
    >>> site = Path(tempfile.mkdtemp())
    >>> _ = (site / "a.html").write_text('<a href="https://x.org">ok</a>\\n'
    ...                                  '<script src="https://cdn.example/m.js"></script>')
    >>> remote_resources(site)
    ['a.html:2: <script> https://cdn.example/m.js']
    """
    found = []
    for path in sorted(site.rglob("*")):
        if path.suffix not in (".html", ".htm", ".css") or not path.is_file():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        where = path.relative_to(site).as_posix()
        if path.suffix == ".css":
            for match in _CSS_URL.finditer(text):
                if _REMOTE.match(match.group(1)):
                    line = text.count("\n", 0, match.start()) + 1
                    found.append(f"{where}:{line}: <css> {match.group(1)}")
            continue
        parser = _Resources()
        parser.feed(text)
        parser.close()
        found += [f"{where}:{line}: <{tag}> {url}" for line, tag, url in parser.found]
    return found


def _visit_math(self: Any, node: Any) -> None:
    from docutils import nodes

    try:
        self.body.append(mathml(node.astext(), display=False))
    except Exception as error:  # latex2mathml raises its own exception types
        _warn(node, error)
        self.body.append(self.encode(node.astext()))
    raise nodes.SkipNode


def _visit_displaymath(self: Any, node: Any) -> None:
    from docutils import nodes
    from sphinx.util.math import get_node_equation_number

    self.body.append(self.starttag(node, "div", CLASS="math"))
    if node["number"]:
        number = get_node_equation_number(self, node)
        self.body.append(f'<span class="eqno">({number})')
        self.add_permalink_ref(node, "Link to this equation")
        self.body.append("</span>")
    # Paragraphs of a math directive are equations of their own (as Sphinx's other renderers).
    for part in (p for p in node.astext().split("\n\n") if p.strip()):
        try:
            self.body.append(mathml(part, display=True))
        except Exception as error:  # latex2mathml raises its own exception types
            _warn(node, error)
            self.body.append(f"<pre>{self.encode(part)}</pre>")
    self.body.append("</div>\n")
    raise nodes.SkipNode


def _warn(node: Any, error: Exception) -> None:
    from sphinx.util import logging

    logging.getLogger(__name__).warning(
        "cannot convert this math to MathML (%s: %s): %s",
        type(error).__name__,
        error,
        node.astext(),
        location=node,
    )


def _check_site(app: Any, exception: Exception | None) -> None:
    if exception is not None or app.builder.format != "html":
        return
    from sphinx.util import logging

    logger = logging.getLogger(__name__)
    for line in remote_resources(Path(app.outdir)):
        logger.warning("the site loads a resource from another host: %s", line)


def setup(app: Any) -> dict[str, Any]:
    """Sphinx entry point."""
    app.add_html_math_renderer(
        "mathml",
        inline_renderers=(_visit_math, None),
        block_renderers=(_visit_displaymath, None),
    )
    app.connect("build-finished", _check_site)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
