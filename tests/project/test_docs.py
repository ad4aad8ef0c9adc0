"""The documentation: nothing points outside the repository; the registry tables are complete."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
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
    from targetacq.acquisition.criteria import CRITERIA
    from targetacq.acquisition.engagement import REDRAW_RULES
    from targetacq.acquisition.path_noise import NOISE_MODELS, SNR_LAWS
    from targetacq.acquisition.probabilities import ACQUISITION_SEMANTICS, MOTION_RULES
    from targetacq.acquisition.transforms import CLUTTER_REGIONS, TRANSFORMS
    from targetacq.physics.atmosphere import EXTINCTION_LEVELS, OBSCURANTS, VISIBILITY_CONVENTIONS
    from targetacq.physics.bands import BANDS
    from targetacq.physics.named_atmospheres import AEROSOLS, PATH_MODELS
    from targetacq.physics.optics import FIELD_OF_VIEW_PROJECTIONS
    from targetacq.physics.targets import TARGETS
    from targetacq.scenario.plausibility import PLAUSIBLE_RANGES
    from targetacq.sensors import SENSOR_TYPES

    expected = {
        "targetacq.acquisition.criteria.CRITERIA": CRITERIA,
        "targetacq.acquisition.transforms.TRANSFORMS": TRANSFORMS,
        "targetacq.acquisition.path_noise.NOISE_MODELS": NOISE_MODELS,
        "targetacq.acquisition.path_noise.SNR_LAWS": SNR_LAWS,
        "targetacq.sensors.SENSOR_TYPES": SENSOR_TYPES,
        "targetacq.physics.targets.TARGETS": TARGETS,
        "targetacq.physics.bands.BANDS": BANDS,
        "targetacq.physics.atmosphere.OBSCURANTS": OBSCURANTS,
        "targetacq.physics.atmosphere.EXTINCTION_LEVELS": EXTINCTION_LEVELS,
        "targetacq.physics.atmosphere.VISIBILITY_CONVENTIONS": VISIBILITY_CONVENTIONS,
        "targetacq.physics.named_atmospheres.PATH_MODELS": PATH_MODELS,
        "targetacq.physics.named_atmospheres.AEROSOLS": AEROSOLS,
        "targetacq.acquisition.transforms.CLUTTER_REGIONS": CLUTTER_REGIONS,
        "targetacq.acquisition.probabilities.MOTION_RULES": MOTION_RULES,
        "targetacq.acquisition.probabilities.ACQUISITION_SEMANTICS": ACQUISITION_SEMANTICS,
        "targetacq.physics.optics.FIELD_OF_VIEW_PROJECTIONS": FIELD_OF_VIEW_PROJECTIONS,
        "targetacq.acquisition.engagement.REDRAW_RULES": REDRAW_RULES,
        # A table of records: each row is named by where its quantity is in a scenario.
        "targetacq.scenario.plausibility.PLAUSIBLE_RANGES": [
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


# --- `make docs` on its own: a fresh venv with only the extras the target installs --------------


def _docs_extras() -> list[str]:
    """The extras the Makefile's docs target installs (``pip install -e '.[docs,...]'``)."""
    text = (ROOT / "Makefile").read_text(encoding="utf-8")
    recipe = re.search(r"^\$\(VENV\)/\.installed-docs:.*\n((?:\t.*\n)+)", text, re.MULTILINE)
    assert recipe, "the Makefile has no $(VENV)/.installed-docs target"
    extras = re.search(r"pip install .*-e '\.\[([^\]]*)\]'", recipe.group(1))
    assert extras, recipe.group(1)
    return [e.strip() for e in extras.group(1).split(",")]


def _installed_closure(requirements: list[str]) -> set[str]:
    """The canonical names of the distributions that ``requirements`` pull in (as pip would:
    extras followed, markers evaluated), read from the installed distributions' metadata."""
    from importlib.metadata import PackageNotFoundError, distribution

    from packaging.requirements import Requirement
    from packaging.utils import canonicalize_name

    seen: set[tuple[str, str]] = set()  # (distribution, extra)
    pending = [(Requirement(r), "") for r in requirements]  # (requirement, extra asking)
    while pending:
        requirement, asking = pending.pop()
        if requirement.marker and not requirement.marker.evaluate({"extra": asking}):
            continue
        name = canonicalize_name(requirement.name)
        for extra in ("", *requirement.extras):
            if (name, extra) in seen:
                continue
            seen.add((name, extra))
            try:
                requires = distribution(name).requires or []
            except PackageNotFoundError:  # not installed here: nothing of it can be imported
                break
            pending += [(Requirement(r), extra) for r in requires]
    return {name for name, _ in seen}


def _site_packages_of(extras: list[str], view: Path) -> Path:
    """A folder of links to the entries of this environment's site-packages that a fresh
    ``pip install -e '.[extras]'`` would install (the closure of the project's requirements),
    and to nothing else: the modules of every other distribution are simply not there."""
    import sysconfig
    from importlib.metadata import packages_distributions

    from packaging.utils import canonicalize_name

    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    optional = config["project"]["optional-dependencies"]
    requirements = list(config["project"]["dependencies"])
    for extra in extras:
        requirements += optional[extra]
    allowed = _installed_closure(requirements) | {"targetacq"}
    owners = {
        module: {canonicalize_name(d) for d in dists}
        for module, dists in packages_distributions().items()
    }
    view.mkdir()
    for folder in dict.fromkeys(sysconfig.get_paths()[k] for k in ("purelib", "platlib")):
        for entry in Path(folder).iterdir():
            if entry.name.endswith(".pth") or (view / entry.name).exists():
                continue  # .pth files are not read here (python -S); src is on the path
            if entry.name.endswith((".dist-info", ".egg-info")):
                dist = canonicalize_name(entry.name.split("-")[0])
                keep = dist in allowed
            else:
                dists = owners.get(entry.name.split(".")[0])
                keep = dists is None or bool(dists & allowed)  # not a module, or one we keep
            if keep:
                (view / entry.name).symlink_to(entry)
    return view


# Imports what the docs build imports: docs/conf.py, every API page's module and the names its
# __all__ lists (autodoc reads them), the pages the extensions generate, and the gallery scripts
# (sphinx-gallery runs them).
DOCS_IMPORTS = """\
import importlib, os, runpy, sys, tempfile
from pathlib import Path

os.environ["MPLBACKEND"] = "Agg"
conf = runpy.run_path({conf!r})
for module in conf["api_modules"]:
    imported = importlib.import_module(module)
    for name in getattr(imported, "__all__", ()):
        getattr(imported, name)
import cli_reference, registry_tables

out = Path(tempfile.mkdtemp())
registry_tables.write_pages(out, conf["api_modules"])
cli_reference.write_reference(out / "cli.rst.inc")
for script in sorted(Path({gallery!r}).glob("plot_*.py")):
    os.chdir(out)
    runpy.run_path(str(script), run_name="__main__")
print("imported", len(conf["api_modules"]), "modules")
"""


def test_make_docs_installs_every_extra_the_docs_import(tmp_path: Path) -> None:
    """`make docs` in a fresh clone installs only the docs target's extras: in an environment
    of just those (this one's site-packages less every other distribution), the docs' modules,
    generated pages and gallery import and run, so the API pages of targetacq.envs and
    targetacq.web render."""
    pytest.importorskip("packaging.requirements")
    extras = _docs_extras()
    assert "docs" in extras
    view = _site_packages_of(extras, tmp_path / "site-packages")
    code = DOCS_IMPORTS.format(
        conf=str(ROOT / "docs" / "conf.py"), gallery=str(ROOT / "docs" / "gallery")
    )
    path = os.pathsep.join([str(ROOT / "src"), str(ROOT / "docs" / "_ext"), str(view)])
    env = {**os.environ, "PYTHONPATH": path}
    done = subprocess.run(
        [sys.executable, "-S", "-c", code],  # -S: no site-packages but the view
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert done.returncode == 0, (
        f"the docs import something `make docs` does not install (extras {extras}):\n"
        + done.stderr[-3000:]
    )
    conf = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    documented = re.findall(r'^\s+"(targetacq[\w.]*)",$', conf, re.MULTILINE)
    assert {"targetacq.envs", "targetacq.web"} <= set(documented)


def test_ci_builds_the_docs_in_a_fresh_venv_of_their_own() -> None:
    """`.ci/run` still runs `make test`, and builds the docs with `make docs` alone in a venv
    that `make test` never installed into (the Makefile's VENV can be set)."""
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^VENV \?= \.venv$", makefile, re.MULTILINE), "VENV must be overridable"
    lines = [
        line.strip()
        for line in (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
        if line.strip() and not line.lstrip().startswith("#")
    ]
    assert "make test" in lines
    docs = [line for line in lines if re.search(r"\bmake docs\b", line)]
    assert docs, "`.ci/run` does not build the docs"
    for line in docs:
        venv = re.match(r"^VENV=(\S+) make docs$", line)
        assert venv and venv.group(1) not in (".venv", ".venv/"), line
        assert f"rm -rf {venv.group(1)}" in lines, f"{venv.group(1)} is not made afresh"


# --- the site works offline: math as MathML, nothing loaded from another host -------------------


@pytest.fixture(scope="module")
def offline():  # the docs' Sphinx extension, docs/_ext/offline.py
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        import offline
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    return offline


def test_remote_resources_are_what_a_page_loads_from_another_host(offline, tmp_path) -> None:
    import doctest

    assert doctest.testmod(offline).failed == 0
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "page.html").write_text(
        '<a href="https://example.org/">a link is not loaded</a>\n'
        '<script src="_static/local.js"></script><script>inline()</script>\n'
        '<script src="//cdn.example/a.js"></script>\n'
        '<link rel="stylesheet" href="https://fonts.example/css">\n'
        '<link rel="canonical" href="https://example.org/page">\n'
        '<img srcset="small.png 1x, http://img.example/big.png 2x">\n'
        '<div style="background: url(https://img.example/b.png)"></div>\n'
        "<style>@import 'https://css.example/x.css';</style>\n",
        encoding="utf-8",
    )
    (tmp_path / "site.css").write_text("a {}\n@import url(https://css.example/y.css);\n")
    assert offline.remote_resources(tmp_path) == [
        "site.css:2: <css> https://css.example/y.css",
        "sub/page.html:3: <script> //cdn.example/a.js",
        "sub/page.html:4: <link> https://fonts.example/css",
        "sub/page.html:6: <img> http://img.example/big.png",
        "sub/page.html:7: <div> https://img.example/b.png",
        "sub/page.html:8: <style> https://css.example/x.css",
    ]


def test_math_converts_to_mathml(offline) -> None:
    pytest.importorskip("latex2mathml")
    block = offline.mathml(r"\frac{1}{\mathrm{SNR}^2} = \sum_i x_i", display=True)
    assert block.startswith('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">')
    assert "<mfrac>" in block and "\\" not in block
    assert 'display="inline"' in offline.mathml("x", display=False)


@pytest.fixture(scope="module")
def small_site(tmp_path_factory) -> tuple[Path, subprocess.CompletedProcess[str]]:
    """The docs' pages built with docs/conf.py and -W, less the gallery (its scripts take
    minutes; a stub stands for its index) and with one API page: a few seconds."""
    pytest.importorskip("sphinx")
    pytest.importorskip("latex2mathml")
    import runpy

    base = tmp_path_factory.mktemp("docs")
    source = base / "source"
    shutil.copytree(
        ROOT / "docs",
        source,
        ignore=shutil.ignore_patterns(
            "_ext", "conf.py", "gallery", "auto_gallery", "generated", "sg_execution_times.rst"
        ),
    )
    (source / "auto_gallery").mkdir()
    (source / "auto_gallery" / "index.rst").write_text("Gallery\n=======\n", encoding="utf-8")
    extensions = runpy.run_path(str(ROOT / "docs" / "conf.py"))["extensions"]
    extensions = [e for e in extensions if not e.startswith("sphinx_gallery")]
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-E",
            "-W",
            "--keep-going",
            "-q",
            "-b",
            "html",
            "-c",
            str(ROOT / "docs"),
            "-D",
            f"extensions={','.join(extensions)}",
            "-D",
            "api_modules=targetacq.base.bundled",
            str(source),
            str(base / "html"),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    return base / "html", done


def test_the_built_site_has_mathml_and_loads_no_remote_script(offline, small_site) -> None:
    site, done = small_site
    assert done.returncode == 0, done.stderr[-3000:]
    assert offline.remote_resources(site) == []
    pages = [p for p in (ROOT / "docs").rglob("*.rst") if ".. math::" in p.read_text("utf-8")]
    assert len(pages) >= 5
    for page in pages:
        html = (site / page.relative_to(ROOT / "docs")).with_suffix(".html").read_text("utf-8")
        assert html.count('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">') >= (
            page.read_text("utf-8").count(".. math::")
        ), page.name
        assert "mathjax" not in html.lower() and "\\frac" not in html, page.name
    for html in site.rglob("*.html"):
        assert not re.search(r"<script[^>]*\bsrc=[\"']?(https?:)?//", html.read_text("utf-8"))


def test_a_page_loading_a_remote_script_fails_the_build(offline, tmp_path) -> None:
    """The extension's check runs in every build: a page that would load a script from another
    host is a warning (an error under -W)."""
    pytest.importorskip("sphinx")
    (tmp_path / "conf.py").write_text(
        f"import sys\nsys.path.insert(0, {str(ROOT / 'docs' / '_ext')!r})\n"
        "extensions = ['offline']\nhtml_math_renderer = 'mathml'\n",
        encoding="utf-8",
    )
    (tmp_path / "index.rst").write_text(
        "Page\n====\n\n:math:`x^2`\n\n.. raw:: html\n\n"
        '   <script src="https://cdn.example/m.js"></script>\n',
        encoding="utf-8",
    )
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-q", "-b", "html", str(tmp_path), str(tmp_path / "o")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert "loads a resource from another host: index.html:" in done.stderr, done.stderr
    assert "https://cdn.example/m.js" in done.stderr
    assert "<math" in (tmp_path / "o" / "index.html").read_text("utf-8")


# --- the command-line reference, generated from the command ------------------------------------


@pytest.fixture(scope="module")
def cli_reference():  # the docs' Sphinx extension, docs/_ext/cli_reference.py
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        import cli_reference
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    return cli_reference


def _help(capsys, monkeypatch, path: tuple[str, ...]) -> str:
    from targetacq.cli import main

    monkeypatch.setenv("COLUMNS", "400")  # no wrapping: one option a line
    capsys.readouterr()
    with pytest.raises(SystemExit) as done:
        main([*path, "--help"])
    assert done.value.code in (0, None)
    return capsys.readouterr().out


def test_the_cli_reference_has_every_command_option_choice_and_default(
    cli_reference, capsys, monkeypatch
) -> None:
    """Each command and sub-command has a section, and every option, choice and default that
    `targetacq ... --help` prints is in it."""
    from targetacq.cli import COMMANDS, all_commands

    docs = cli_reference.commands()
    text = cli_reference.render(docs)
    paths = [d.path for d in docs]
    assert paths[0] == () and set(COMMANDS) <= {p[0] for p in paths if p}
    assert ("examples", "copy") in paths and ("examples", "list") in paths
    assert set(all_commands()) == {p[0] for p in paths if len(p) == 1}
    sections = re.split(r"^\.\. _(cli[\w-]*):$", text, flags=re.MULTILINE)[1:]
    by_label = dict(zip(sections[::2], sections[1::2], strict=True))
    assert list(by_label) == [d.label for d in docs]
    for doc in docs:
        section = " ".join(by_label[doc.label].split())
        assert f"``{doc.name}``" in section
        printed = _help(capsys, monkeypatch, doc.path)
        for option in set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", printed)) - {"--help"}:
            assert f"``{option}" in section or f"/ {option}" in section or option in section, (
                doc.name,
                option,
            )
        for default in re.findall(r"\[default: ([^\]]+)\]", printed):
            assert f"``{default.strip()}``" in section, (doc.name, default)
        for line in printed.splitlines():  # the registries' choices, as the help lists them
            choices = re.search(r"(?:Criteria set|Transform|Noise model): ([^()]+)", line)
            if choices:
                listed = choices.group(1).split("(")[0].split("│")[0].strip(" .,")
                assert listed in section, (doc.name, line)
    assert "sweep" in text and "design" in text and "report" in text


def test_the_cli_reference_page_includes_the_generated_text() -> None:
    page = (ROOT / "docs" / "cli.rst").read_text(encoding="utf-8")
    assert ".. include:: /generated/cli.rst.inc" in page
    assert "list-table" not in page and "--focal-length" not in page  # no option typed by hand
    index = (ROOT / "docs" / "index.rst").read_text(encoding="utf-8")
    assert "\n   cli\n" in index and "\n   trade_study\n" in index
