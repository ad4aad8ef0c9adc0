"""Compute engines: the array core run by NumPy (the reference), numba or JAX.

An engine evaluates the core of :mod:`targetacq.core.evaluation` — factors, then probabilities
and their fusion — for a scene. :data:`ENGINES` is the registry; pick one by name with
``engine=`` in :class:`targetacq.ModelChain`, :class:`targetacq.Simulation` and the commands
that evaluate (``--engine``):

``numpy`` (default)
    :mod:`targetacq.core.evaluation` itself: the reference, always available.
``numba``
    The same pipeline compiled into two fused loops (:mod:`targetacq.core.engines.numba_engine`);
    ``pip install 'targetacq[fast]'``. Equal to the NumPy engine to about 1e-15 relative on
    the probabilities (tested to 1e-12) and exactly on the field of view, for float64 input (it
    computes in float64 whatever the input); the transforms ``ttpf`` and ``c2nveo`` and every
    noise model, motion rule and semantics of the registries. Compiled on first use and cached
    on disk: about a minute once per installation, then none.
``jax``
    The core under ``jax.jit`` in float64, on JAX's default device (a GPU where JAX has one):
    one jitted call from positions to probabilities, in chunks of a fixed shape so that a run
    compiles once (:mod:`targetacq.core.engines.jax_engine`); NumPy arrays in and out; equal to
    the NumPy engine to about 1e-12. ``pip install 'targetacq[jax]'`` (CPU) or
    ``'targetacq[jax-cuda]'`` (NVIDIA GPU, CUDA 12).
``auto``
    ``numba`` where it is installed and compiles the scene (its choices; no radars, laser
    radars, MRTD-limited sensors, the TTP resolution model, foliage, a digitiser's step, graded
    cues or airlight:
    :func:`targetacq.core.engines.numba_engine.supported`),
    else ``numpy``; the step API (:class:`targetacq.Simulation`) too (:func:`for_steps`): a
    time's pairs go through the numba engine's pair kernels in one call each
    (``benchmarks/bench_step.py``).

Every engine takes NumPy positions and gives the records of the core
(:class:`targetacq.core.Factors`, :class:`targetacq.core.Probabilities`) in NumPy arrays, so
the steps that follow (terrain clutter, the draws of the step API, the writers) do not depend
on the engine.

Examples
--------
>>> from targetacq.core.engines import ENGINES, get_engine
>>> sorted(ENGINES)
['auto', 'jax', 'numba', 'numpy']
>>> get_engine("numpy").name
'numpy'
"""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Protocol

from targetacq.base.arrays import Array
from targetacq.base.registry import lookup
from targetacq.core.evaluation import evaluate_step, factors, probabilities

__all__ = ["ENGINES", "BoundEngine", "Engine", "bind", "engine_names", "for_steps", "get_engine"]


class BoundEngine(Protocol):
    """An engine bound to one scene: what :func:`bind` returns."""

    engine: str
    """The engine's name (``auto`` resolved)."""

    def factors(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        scr: Any = None,
        visible_fraction: Any = None,
    ) -> Any:
        """:func:`targetacq.core.factors` of the scene (``visible_fraction``: the targets'
        visible fraction for this call, replacing the scene's)."""

    def probabilities(self, found: Any, moving: Any = None) -> Any:
        """:func:`targetacq.core.probabilities` of the scene (``moving``: the targets' moving
        flags for this call, replacing the scene's)."""

    def step(
        self,
        sensor_positions: Array,
        target_positions: Array,
        headings: Array = None,
        pointing: Array = None,
        visible_fraction: Array = None,
        moving: Array = None,
        scr: Array = None,
    ) -> tuple[Any, Any, Any]:
        """One time, lean: :func:`targetacq.core.evaluate_step` of the scene.

        Parameters
        ----------
        sensor_positions : numpy.ndarray (n_s, 3)
            [m] (east, north, up).
        target_positions : numpy.ndarray (n_g, 3)
            [m].
        headings : numpy.ndarray (n_g,), optional
            [rad]; default the targets' own.
        pointing : numpy.ndarray (n_s, 2), optional
            Azimuth and depression [rad]; a NaN row keeps the sensor's own pointing.
        visible_fraction : numpy.ndarray, optional
            ``(n_g,)`` or ``(n_s, n_g)``, in (0, 1], replacing the targets' own.
        moving : numpy.ndarray of bool (n_g,), optional
            Replacing the targets' own flags.
        scr : numpy.ndarray (n_s, n_g), optional
            SCR per pair, replacing the scene's (e.g. a terrain map's).

        Returns
        -------
        in_view : numpy.ndarray of bool (n_s, n_g)
        probabilities : numpy.ndarray (3, n_s, n_g)
            Detection, recognition, identification (zero outside the field of view, NaN for
            unknown geometry).
        fused : numpy.ndarray (3, n_g)
            Their sensor-level fusion (8.4).

        The numbers of :meth:`factors` then :meth:`probabilities` (``in_view`` exactly, the
        probabilities to about 1e-15 relative), without the other factors: the NumPy engine
        runs the chain on the pairs in view only, the numba engine in one kernel call.
        """


@dataclass(frozen=True)
class Engine:
    """A compute engine in the registry.

    Attributes
    ----------
    name : str
    bind : callable
        ``bind(scene) -> BoundEngine``.
    module : str or None
        The optional package it needs (None: none).
    extra : str or None
        The extra that installs it (``pip install 'targetacq[extra]'``).
    description : str
    """

    name: str
    bind: Callable[[Any], BoundEngine]
    module: str | None
    extra: str | None
    description: str

    def available(self) -> bool:
        """Whether the package it needs is installed and imports (numba refuses to import
        with a NumPy newer than it supports)."""
        if self.module is None:
            return True
        if importlib.util.find_spec(self.module) is None:
            return False
        try:
            importlib.import_module(self.module)
        except ImportError:
            return False
        return True


class NumpyScene:
    """A scene bound to the NumPy engine: the core's functions, as they are."""

    engine = "numpy"

    def __init__(self, scene: Any) -> None:
        self.scene = scene

    def factors(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        scr: Any = None,
        visible_fraction: Any = None,
    ) -> Any:
        return factors(
            self.scene,
            sensor_positions,
            target_positions,
            headings,
            pointing,
            scr,
            visible_fraction,
        )

    def probabilities(self, found: Any, moving: Any = None) -> Any:
        return probabilities(self.scene, found, moving)

    def step(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        visible_fraction: Any = None,
        moving: Any = None,
        scr: Any = None,
    ) -> tuple[Any, Any, Any]:
        return evaluate_step(
            self.scene,
            sensor_positions,
            target_positions,
            headings,
            pointing,
            visible_fraction,
            moving,
            scr,
        )


def _bind_numpy(scene: Any) -> BoundEngine:
    return NumpyScene(scene)


def _bind_numba(scene: Any) -> BoundEngine:
    from targetacq.core.engines.numba_engine import NumbaScene

    return NumbaScene(scene)


def _bind_jax(scene: Any) -> BoundEngine:
    from targetacq.core.engines.jax_engine import JaxScene

    return JaxScene(scene)


def _bind_auto(scene: Any) -> BoundEngine:
    if ENGINES["numba"].available():
        from targetacq.core.engines.numba_engine import supported

        if supported(scene) is None:
            return _bind_numba(scene)
    return NumpyScene(scene)


ENGINES = MappingProxyType(
    {
        "numpy": Engine("numpy", _bind_numpy, None, None, "the array core in NumPy: the reference"),
        "numba": Engine(
            "numba",
            _bind_numba,
            "numba",
            "fast",
            "the core's pipeline compiled by numba into two fused loops",
        ),
        "jax": Engine(
            "jax",
            _bind_jax,
            "jax",
            "jax",
            "the array core under jax.jit in float64, on JAX's default device",
        ),
        "auto": Engine(
            "auto", _bind_auto, None, None, "numba where installed and able, else numpy"
        ),
    }
)
"""Compute engines by name (read-only)."""


def engine_names() -> tuple[str, ...]:
    """The registered engines' names, for choices (CLI, schema, docs)."""
    return tuple(ENGINES)


def get_engine(engine: str | Engine) -> Engine:
    """Resolve an engine by name.

    Raises
    ------
    ValueError
        An unknown name (listing the valid ones), or an engine whose package is not installed
        (saying which extra installs it).

    Examples
    --------
    >>> from targetacq.core.engines import get_engine
    >>> get_engine("numpy").available()
    True
    """
    chosen = engine if isinstance(engine, Engine) else lookup(ENGINES, engine, "engine")
    if not chosen.available():
        raise ValueError(
            f"engine {chosen.name!r} needs the package {chosen.module!r}: "
            f"pip install 'targetacq[{chosen.extra}]' (or use engine='numpy')"
        )
    return chosen


def for_steps(engine: str | Engine) -> Engine:
    """The engine for the step API: the engine named (:func:`get_engine`). ``auto`` binds the
    numba engine where it is installed and compiles the scene (its pair kernels run one time's
    pairs in one call, faster than NumPy at every size of ``benchmarks/bench_step.py``), else
    the NumPy engine.

    Examples
    --------
    >>> from targetacq.core.engines import for_steps
    >>> for_steps("numpy").name
    'numpy'
    """
    return get_engine(engine)


def bind(scene: Any, engine: str | Engine = "numpy") -> BoundEngine:
    """The engine bound to a scene (:class:`targetacq.core.SceneArrays`).

    Parameters
    ----------
    scene : SceneArrays
    engine : str or Engine
        :data:`ENGINES`.

    Returns
    -------
    BoundEngine
        With ``factors(sensor_positions, target_positions, headings=None, pointing=None,
        scr=None)`` and ``probabilities(factors)``, as :mod:`targetacq.core.evaluation`.

    Raises
    ------
    ValueError
        An unknown or unavailable engine, or a scene it cannot evaluate (the message says
        which choice).
    """
    return get_engine(engine).bind(scene)
