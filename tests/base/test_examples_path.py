"""targetacq.example_path: a bundled example's path, from a checkout, an installed wheel or a
zipped package (the wheel itself is installed and checked by ``.ci/package``)."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import targetacq
from targetacq.base.bundled import example_files, example_name, example_path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def test_every_bundled_example_has_a_path_by_its_name_and_without_its_suffix() -> None:
    names = list(example_files())
    assert {"uav_haze.toml", "scene.png", "targets.csv", "frame16.tif"} <= set(names)
    for name in names:
        path = example_path(name)
        assert isinstance(path, Path) and path.is_file() and path.name == name
        assert path.read_bytes() == (EXAMPLES / name).read_bytes()
        assert example_path(Path(name).stem) == path
        assert example_name(Path(name).stem) == name
    assert targetacq.example_path is example_path
    assert "example_path" in targetacq.__all__


def test_an_example_path_is_what_the_readme_snippet_loads(tmp_path, monkeypatch) -> None:
    """The README's scenario snippet from a folder without ``examples/`` (as from a wheel)."""
    from targetacq.run.model_chain import ModelChain
    from targetacq.scenario.schema import load_scenario

    monkeypatch.chdir(tmp_path)
    chain = ModelChain(load_scenario(targetacq.example_path("uav_haze")))
    assert chain.evaluate().dataset["detection"].shape == (1, 3, 13)


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("uav_hase", "unknown example 'uav_hase' (did you mean 'uav_haze.toml'?); valid: "),
        ("uav_haze.tml", "(did you mean 'uav_haze.toml'?)"),
        ("nothing-like-it", "unknown example 'nothing-like-it'; valid: colour_camera.toml, "),
        ("", "unknown example ''; valid: "),
        ("examples/uav_haze.toml", "unknown example 'examples/uav_haze.toml'"),
    ],
)
def test_an_unknown_example_is_refused_with_the_closest_and_the_valid_names(name, message):
    with pytest.raises(ValueError, match="valid: ") as refused:
        example_path(name)
    assert message in str(refused.value)
    for valid in example_files():
        assert valid in str(refused.value)


@pytest.mark.parametrize("name", [None, 3, Path("uav_haze.toml"), b"uav_haze"])
def test_an_example_name_must_be_text(name) -> None:
    with pytest.raises(TypeError, match="must be a str"):
        example_path(name)


def test_example_path_from_a_zipped_package(tmp_path) -> None:
    """A package imported from a zip file has no file on disk: the example is extracted once,
    to a real file with the same bytes."""
    archive = tmp_path / "targetacq.zip"
    source = ROOT / "src"
    with zipfile.ZipFile(archive, "w") as zipped:
        for folder, _, files in os.walk(source / "targetacq", followlinks=True):  # examples/
            for name in sorted(files):
                path = Path(folder) / name
                if "__pycache__" not in path.parts:
                    zipped.write(path, path.relative_to(source).as_posix())
    code = (
        "import targetacq, sys\n"
        "assert targetacq.__file__.startswith(sys.argv[1]), targetacq.__file__\n"
        "path = targetacq.example_path('uav_haze')\n"
        "assert path.is_file() and not str(path).startswith(sys.argv[1])\n"
        "print(path.read_bytes() == open(sys.argv[2], 'rb').read())\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(archive)
    done = subprocess.run(
        [sys.executable, "-c", code, str(archive), str(EXAMPLES / "uav_haze.toml")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=env,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0 and done.stdout.strip() == "True", done.stderr[-2000:]


def test_the_wheel_check_loads_an_example_by_its_path() -> None:
    """`.ci/package` runs the README's way to a bundled example from the installed wheel, in a
    folder without the examples."""
    script = (ROOT / ".ci" / "package").read_text(encoding="utf-8")
    check = script[script.index("# --- run it from outside the repository") :]
    assert "example_path(" in check
    assert check.index("example_path(") < check.index("targetacq examples copy")
