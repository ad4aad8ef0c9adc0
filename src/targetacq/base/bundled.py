"""The example files bundled with the package: scenario files, scripts, images and box files.

They are package data (``targetacq/examples`` in a wheel; the repository's ``examples/`` in a
checkout), found with :mod:`importlib.resources`, so the same code finds them in an installed
wheel as in a checkout. :func:`example_path` gives one's path, for Python code that needs a file
(``load_scenario(example_path("uav_haze"))``); ``targetacq examples list`` and
``targetacq examples copy`` list them and copy them into a folder of your own.
"""

from __future__ import annotations

import atexit
import contextlib
from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path

from targetacq.base.registry import unknown_name

__all__ = ["example_files", "example_name", "example_path"]

_EXTRACTED = contextlib.ExitStack()  # files copied out of a zipped install, kept until exit
atexit.register(_EXTRACTED.close)


def example_files() -> dict[str, Traversable]:
    """The bundled example files: file name → resource, sorted by name.

    Examples
    --------
    >>> "uav_haze.toml" in example_files()
    True
    """
    folder = resources.files("targetacq").joinpath("examples")
    files = {
        entry.name: entry
        for entry in folder.iterdir()
        if entry.is_file() and not entry.name.startswith((".", "_"))
    }
    return dict(sorted(files.items()))


def example_name(name: str) -> str:
    """The file name of a bundled example given its file name or its name without the suffix.

    Parameters
    ----------
    name : str
        ``"uav_haze.toml"`` or ``"uav_haze"`` (``targetacq examples list`` lists them).

    Returns
    -------
    str
        The file name, ``"uav_haze.toml"``.

    Raises
    ------
    TypeError
        If ``name`` is not a string.
    ValueError
        For a name that is no bundled example: the closest one ("did you mean") and every valid
        name.

    Examples
    --------
    >>> example_name("uav_haze")
    'uav_haze.toml'
    >>> example_name("uav_hase")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: unknown example 'uav_hase' (did you mean 'uav_haze.toml'?); valid: ...
    """
    if not isinstance(name, str):
        raise TypeError(f"an example's name must be a str, not {type(name).__name__}")
    names = list(example_files())
    if name in names:
        return name
    stems: dict[str, list[str]] = {}
    for file in names:
        stems.setdefault(Path(file).stem, []).append(file)
    if len(stems.get(name, ())) == 1:
        return stems[name][0]
    if name in stems:  # two files with that stem: the suffix decides
        raise ValueError(f"example {name!r} is ambiguous: give one of {', '.join(stems[name])}")
    raise unknown_name(name, names, "example")


def example_path(name: str) -> Path:
    """The path of a bundled example file, to read or to pass to functions that take a path.

    Works from an installed wheel as from a checkout: no need to copy the examples first (use
    ``targetacq examples copy`` to get copies you can edit). The file is the package's own:
    read it, do not change it.

    Parameters
    ----------
    name : str
        The example's file name, or its name without the suffix: ``"uav_haze"``,
        ``"uav_haze.toml"``, ``"scene.png"``. ``targetacq examples list`` lists them.

    Returns
    -------
    pathlib.Path
        The file (inside the installed package; for a package imported from a zip file, a
        copy extracted once for the life of the process).

    Raises
    ------
    TypeError
        If ``name`` is not a string.
    ValueError
        For a name that is no bundled example, with the closest name ("did you mean") and the
        valid names.

    Examples
    --------
    >>> from targetacq.scenario.schema import load_scenario
    >>> path = example_path("uav_haze")
    >>> path.name
    'uav_haze.toml'
    >>> load_scenario(path).name
    'UAV over vehicles in haze'
    """
    file = example_name(name)
    resource = example_files()[file]
    if isinstance(resource, Path):
        return resource
    return _EXTRACTED.enter_context(resources.as_file(resource))
