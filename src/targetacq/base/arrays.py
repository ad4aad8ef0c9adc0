"""Array namespace handling and input checks shared by the kernels.

Kernels are written against the Python array API standard: they take the namespace of their
inputs from :func:`array_api_compat.array_namespace`, so NumPy arrays stay NumPy and e.g.
``array_api_strict`` or CuPy arrays stay in their library. Python scalars and lists become
NumPy float64 arrays unless another input fixes the namespace. A 0-d NumPy result is returned
as a NumPy scalar, so scalar in gives scalar out.

Units. The kernels take bare SI numbers (m, rad, K, s, ...). A pint ``Quantity`` given to a
kernel is converted to its magnitude in SI base units by :func:`as_float` and :func:`arrays`
(:func:`targetacq.base.units.si_magnitude`): ``ifov(17 * ureg.um, 75 * ureg.mm)`` is 17e-6 / 75e-3,
a temperature in degC becomes kelvin, an angle in degrees radians, and a dimensionless quantity
its plain number. The kernel does not know which dimension it expects, so a quantity of the
wrong dimension is not caught here: pass the dimension the parameter documents. pint is never
imported for this: a value can only be a quantity once pint has been imported.

Checks follow one rule: a bad scalar raises ``ValueError`` naming the input and the valid range;
inside an array, NaN propagates as NaN (a batch never fails half-way for a missing value), but
values that are out of range (negative lengths, probabilities above one) raise for the whole
batch before anything is computed.

Validation policy under tracing. A check needs the values on the host, which a function traced by
``jax.jit``, ``vmap`` or ``grad`` does not have. The checks below therefore run only on concrete
arrays: called on a tracer, or under ``jax.jit`` (where even operations on constant arrays are
staged, :func:`any_known`), they do nothing, and the kernel's NaN-masking carries a bad value
through as NaN. The public entry points (scenario compilation, the step API, the CLI) check
their inputs on the host before anything is traced, so the clear ``ValueError`` stays where a
user meets it.

Infinities. Where a kernel's formula has a limit at infinity that its docstring states (an
infinite SNR or SCR: no noise or no clutter; an infinite range or extinction: nothing
transmitted; infinitely many cycles: P = 1) an infinite input gives that limit. Where it has none
(angles, hours, positions), the kernel refuses it with ``ValueError`` naming the input
(:func:`require_finite`), for the whole batch like any other out-of-range value.

Data types. The kernels compute with real floating-point numbers. :func:`as_float` and
:func:`arrays` take real floats as they are (float32 stays float32) and convert integers to
float64; anything else raises ``TypeError`` naming the input where the kernel gives its name:
complex numbers (whose imaginary part would be dropped silently), booleans (True is not a
temperature or a range; flags such as ``hot_spot`` are separate parameters), strings and bytes
(``"3"`` is not the number 3), dates and durations (give seconds), and object arrays (e.g. a
list holding ``None``: give NaN for a missing value).

Masked arrays (:class:`numpy.ma.MaskedArray`) are refused with ``TypeError``: the kernels would
compute under the mask and return a plain array, so the mask would be lost silently. The missing
value of the kernels is NaN: pass ``value.filled(numpy.nan)`` and every masked element comes out
as NaN, the rest unchanged.

Broadcasting. Inputs that broadcast together elementwise are checked up front by
:func:`arrays` given their ``names``: inputs that do not broadcast raise ``ValueError`` naming
each input and its shape (``cycles (3,) and snr (2,) do not broadcast``), not NumPy's text from
the middle of the kernel.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import array_api_compat
import numpy as np

from targetacq.base.limits import check_finite
from targetacq.base.units import is_quantity, si_magnitude

Array = Any  # an array of any array-API namespace


NUMPY = array_api_compat.array_namespace(np.empty(0))
# Types that are NumPy (or plain numbers NumPy takes): the common case, answered without asking
# array_api_compat, whose look-ups cost microseconds a call on the step API's small arrays.
_PLAIN = (np.ndarray, np.float64, float, int, type(None))


def _is_array(value: object) -> bool:
    if type(value) is np.ndarray:
        return True
    return array_api_compat.is_array_api_obj(value) and not isinstance(value, (int, float))


def namespace(*values: object) -> Any:
    """The array namespace of the array inputs (NumPy when all are Python scalars or lists)."""
    if all(type(v) in _PLAIN for v in values):
        return NUMPY
    arrays = [v for v in values if v is not None and _is_array(v)]
    if not arrays:
        return NUMPY
    return array_api_compat.array_namespace(*arrays)


def _refuse(name: str | None, got: str) -> TypeError:
    what = name or "an input of the kernel"
    return TypeError(f"{what} must be real numbers; got {got}")


def _check_numpy_dtype(value: np.ndarray | np.generic, name: str | None) -> None:
    """Raise ``TypeError`` unless a NumPy array holds real floats or integers (module doc)."""
    kind = value.dtype.kind
    if kind in "fiu":
        return
    if kind == "b":
        raise _refuse(name, "booleans (True/False)")
    if kind == "c":
        raise _refuse(name, f"{value.dtype} (the imaginary part would be lost)")
    if kind in "US":
        raise _refuse(name, f"text ({value.dtype})")
    if kind in "mM":
        raise _refuse(name, f"{value.dtype} (give times and durations in seconds)")
    raise _refuse(name, f"{value.dtype} values (give NaN, not None, for a missing value)")


def as_float(value: object, xp: Any, name: str | None = None) -> Array:
    """``value`` as a floating array of namespace ``xp`` (float64 for integer input).

    A pint ``Quantity`` becomes its magnitude in SI base units (see the module docstring).

    Raises
    ------
    TypeError
        For a value that is not real numbers (complex, boolean, text, dates, objects) or a
        masked array (module docstring), naming ``name`` where given.
    """
    if type(value) is np.ndarray and xp is NUMPY and value.dtype == np.float64:
        return value
    if type(value) in (float, int) and xp is NUMPY:
        return np.asarray(value, dtype=np.float64)
    if is_quantity(value):
        value = si_magnitude(value)
    if isinstance(value, np.ma.MaskedArray):
        raise TypeError(
            f"{name or 'an input of the kernel'} is a masked array, whose mask the kernels "
            "would lose; pass value.filled(numpy.nan): NaN is the missing value, and comes "
            "out as NaN"
        )
    if _is_array(value):
        dtype = getattr(value, "dtype", None)
        if isinstance(value, (np.ndarray, np.generic)):
            _check_numpy_dtype(value, name)
            if value.dtype.kind == "f":
                return value
        elif dtype is not None:
            if xp.isdtype(dtype, "real floating"):
                return value
            if not xp.isdtype(dtype, "integral"):
                raise _refuse(name, f"{dtype}")
        return xp.astype(value, xp.float64)
    if isinstance(value, (bool, np.bool_)):
        raise _refuse(name, "booleans (True/False)")
    if isinstance(value, (str, bytes)):
        raise _refuse(name, f"text ({value!r})")
    plain = np.asarray(value)
    _check_numpy_dtype(plain, name)
    if xp is NUMPY:
        return plain.astype(np.float64, copy=False)
    return xp.asarray(plain, dtype=xp.float64)


def check_broadcast(names: Sequence[str], values: Sequence[Array]) -> None:
    """Raise ``ValueError`` naming the inputs and their shapes unless they broadcast together.

    One comparison of shapes where they agree (the common case); NumPy's broadcasting rule
    otherwise.

    Examples
    --------
    >>> check_broadcast(("cycles", "snr"), (np.ones(3), np.ones(2)))
    Traceback (most recent call last):
    ...
    ValueError: cycles (3,) and snr (2,) do not broadcast
    """
    shapes = [tuple(v.shape) for v in values]
    distinct = {s for s in shapes if s}
    if len(distinct) <= 1:
        return
    try:
        np.broadcast_shapes(*shapes)
    except ValueError:
        given = [f"{n} {s}" for n, s in zip(names, shapes, strict=True) if s]
        listed = ", ".join(given[:-1]) + f" and {given[-1]}"
        raise ValueError(f"{listed} do not broadcast") from None


def arrays(
    *values: object, names: Sequence[str] | None = None, broadcast: bool = True
) -> tuple[Any, list[Array]]:
    """The common namespace and each value as a floating array of it.

    pint quantities are first replaced by their SI magnitudes, whose arrays fix the namespace.

    Parameters
    ----------
    *values
        Array-likes, Python numbers or pint quantities.
    names : sequence of str, optional
        The inputs' names, for a kernel whose inputs broadcast together elementwise: a value of
        the wrong dtype is named in the ``TypeError``, and inputs that do not broadcast raise
        ``ValueError`` naming them and their shapes (:func:`check_broadcast`). Without names
        (inputs of different roles, e.g. a grid and values on it) the shapes are not checked.
    broadcast : bool
        With ``names``, whether the inputs must broadcast together (False: they are only
        named, e.g. positions of sensors and of targets).

    Raises
    ------
    TypeError
        A value that is not real numbers, or a masked array (:func:`as_float`).
    """
    if not all(type(v) in _PLAIN for v in values):
        values = tuple(si_magnitude(v) if is_quantity(v) else v for v in values)
    xp = namespace(*values)
    if names is None:
        return xp, [as_float(v, xp) for v in values]
    converted = [as_float(v, xp, n) for v, n in zip(values, names, strict=True)]
    if broadcast:
        check_broadcast(names, converted)
    return xp, converted


def result(value: Array) -> Any:
    """Return 0-d NumPy arrays as NumPy scalars; everything else unchanged."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return value[()]
    return value


def chunked_elementwise(function: Any, value: Array, chunk: int = 1 << 14) -> Array:
    """Apply an elementwise ``function`` to a large NumPy array in cache-sized chunks.

    Long chains of array operations run several times faster when their temporaries stay in
    the CPU cache; other namespaces (and small arrays) get one call on the whole array.
    """
    if not isinstance(value, np.ndarray) or value.size <= chunk:
        return function(value)
    flat = value.reshape(-1)
    out = np.empty(flat.shape, dtype=np.result_type(value.dtype, np.float64))
    for start in range(0, flat.size, chunk):
        out[start : start + chunk] = function(flat[start : start + chunk])
    return out.reshape(value.shape)


def is_traced(value: object) -> bool:
    """Whether ``value`` is an abstract JAX tracer (inside ``jit``, ``vmap`` or ``grad``).

    JAX is never imported here: a value can only be a tracer once JAX has been imported.
    """
    import sys

    jax = sys.modules.get("jax")
    return jax is not None and isinstance(value, jax.core.Tracer)


def any_known(mask: Array, xp: Any) -> bool:
    """Whether any element of a bool array is true, as far as the host can know.

    False where the answer is traced: under ``jax.jit`` every operation is staged, so even a
    mask of constant arrays is a tracer there (the validation policy, module docstring).
    """
    found = xp.any(mask)
    return False if is_traced(found) else bool(found)


def _describe(value: Array, xp: Any, mask: Array) -> str:
    bad = value[mask] if value.ndim else value
    first = float(xp.reshape(bad, (-1,))[0]) if value.ndim else float(value)
    return f"{first:g}" if value.ndim == 0 else f"{first:g} (and possibly others)"


def _check_scalar_nan(name: str, value: Array, xp: Any, valid: str) -> None:
    if is_traced(value):
        return
    if value.ndim == 0 and any_known(xp.isnan(value), xp):
        raise ValueError(f"{name} must be {valid}, got NaN")


def require_flag(name: str, value: object, *, arrays: bool) -> None:
    """Raise ``TypeError`` unless ``value`` is True or False (or, with ``arrays``, a bool array).

    Truthiness would read ``"no"`` as True: a flag states a fact about the target, never a
    guess from text or numbers.
    """
    if isinstance(value, (bool, np.bool_)):
        return
    if arrays and str(getattr(value, "dtype", "")) == "bool":
        return
    if arrays:
        raise TypeError(
            f"{name} must be True, False or a boolean array; got {type(value).__name__} {value!r}"
        )
    raise TypeError(f"{name} must be True or False, got {value!r}")


def require_positive(name: str, value: Array, xp: Any, unit: str = "") -> None:
    """Raise ``ValueError`` unless every non-NaN element is > 0 (a scalar NaN also raises)."""
    valid = f"> 0{' ' + unit if unit else ''}"
    _check_scalar_nan(name, value, xp, valid)
    if is_traced(value):
        return
    mask = value <= 0
    if any_known(mask, xp):
        raise ValueError(f"{name} must be {valid}, got {_describe(value, xp, mask)}")


def require_nonnegative(name: str, value: Array, xp: Any, unit: str = "") -> None:
    """Raise ``ValueError`` unless every non-NaN element is >= 0 (a scalar NaN also raises)."""
    valid = f">= 0{' ' + unit if unit else ''}"
    _check_scalar_nan(name, value, xp, valid)
    if is_traced(value):
        return
    mask = value < 0
    if any_known(mask, xp):
        raise ValueError(f"{name} must be {valid}, got {_describe(value, xp, mask)}")


def require_where(name: str, value: Array, mask: Array, xp: Any, valid: str) -> None:
    """Raise ``ValueError`` where ``mask`` holds at a known element; NaN (scalars too) passes.

    The check of the kernels whose NaN inputs give NaN outputs even as scalars (the MTFs, the
    MRTD and the TTP metric): ``mask`` marks the out-of-range elements, ``valid`` says what is
    valid ("> 0 m").

    Examples
    --------
    >>> import numpy as np
    >>> require_where("range", np.float64("nan"), np.False_, np, "> 0 m")  # NaN passes
    >>> require_where("range", np.float64(-1.0), np.True_, np, "> 0 m")
    Traceback (most recent call last):
    ...
    ValueError: range must be > 0 m, got -1
    """
    if is_traced(value) or not any_known(mask, xp):
        return
    bad = value[mask] if value.ndim else value
    first = float(xp.reshape(bad, (-1,))[0])
    raise ValueError(f"{name} must be {valid}, got {first:g}")


def require_positive_or_nan(name: str, value: Array, xp: Any, unit: str = "") -> None:
    """:func:`require_where` of ``value > 0`` (NaN passes, scalars too)."""
    require_where(name, value, value <= 0, xp, f"> 0{' ' + unit if unit else ''}")


def require_nonnegative_or_nan(name: str, value: Array, xp: Any, unit: str = "") -> None:
    """:func:`require_where` of ``value >= 0`` (NaN passes, scalars too)."""
    require_where(name, value, value < 0, xp, f">= 0{' ' + unit if unit else ''}")


def require_unit_interval(name: str, value: Array, xp: Any) -> None:
    """Raise ``ValueError`` unless every non-NaN element lies in [0, 1]."""
    _check_scalar_nan(name, value, xp, "in [0, 1]")
    if is_traced(value):
        return
    mask = (value < 0) | (value > 1)
    if any_known(mask, xp):
        raise ValueError(f"{name} must be in [0, 1], got {_describe(value, xp, mask)}")


def require_open_unit_interval(name: str, value: Array, xp: Any) -> None:
    """Raise ``ValueError`` unless every non-NaN element lies in the open interval (0, 1)."""
    _check_scalar_nan(name, value, xp, "in the open interval (0, 1)")
    if is_traced(value):
        return
    mask = (value <= 0) | (value >= 1)
    if any_known(mask, xp):
        raise ValueError(
            f"{name} must be in the open interval (0, 1), got {_describe(value, xp, mask)}"
        )


def require_finite(name: str, value: Array, xp: Any, unit: str = "") -> None:
    """Raise ``ValueError`` unless every non-NaN element is finite (a scalar NaN also raises).

    A scalar is refused in the words of :func:`targetacq.base.limits.check_finite`, as at the
    other front-ends; an array names the first infinite value.
    """
    if is_traced(value):
        return
    if value.ndim == 0:
        check_finite(name, float(value))
        return
    mask = xp.isinf(value)
    if any_known(mask, xp):
        first = float(xp.reshape(value[mask], (-1,))[0])
        raise ValueError(
            f"{name} must be finite; got {first:g}{' ' + unit if unit else ''} "
            "(an overflowing number?)"
        )


def require_in_range(
    name: str, value: Array, xp: Any, low: float, high: float, unit: str = "", scale: float = 1.0
) -> None:
    """Raise ``ValueError`` unless every non-NaN element lies in [low, high] (a scalar NaN also
    raises); ``scale`` converts to the ``unit`` of the message, as
    :func:`targetacq.base.limits.check_range` words it."""
    suffix = f" {unit}" if unit else ""
    valid = f"in [{low * scale:g}, {high * scale:g}]{suffix}"
    _check_scalar_nan(name, value, xp, valid)
    if is_traced(value):
        return
    mask = (value < low) | (value > high)
    if any_known(mask, xp):
        bad = value[mask] if value.ndim else value
        first = float(xp.reshape(bad, (-1,))[0]) * scale
        raise ValueError(f"{name} must be {valid}; got {first:g}{suffix}")
