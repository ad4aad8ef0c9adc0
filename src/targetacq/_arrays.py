"""Array namespace handling and input checks shared by the kernels.

Kernels are written against the Python array API standard: they take the namespace of their
inputs from :func:`array_api_compat.array_namespace`, so NumPy arrays stay NumPy and e.g.
``array_api_strict`` or CuPy arrays stay in their library. Python scalars and lists become
NumPy float64 arrays unless another input fixes the namespace. A 0-d NumPy result is returned
as a NumPy scalar, so scalar in gives scalar out.

Units. The kernels take bare SI numbers (m, rad, K, s, ...). A pint ``Quantity`` given to a
kernel is converted to its magnitude in SI base units by :func:`as_float` and :func:`arrays`
(:func:`targetacq.units.si_magnitude`): ``ifov(17 * ureg.um, 75 * ureg.mm)`` is 17e-6 / 75e-3,
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
"""

from __future__ import annotations

from typing import Any

import array_api_compat
import numpy as np

from targetacq.units import is_quantity, si_magnitude

Array = Any  # an array of any array-API namespace


_NUMPY = array_api_compat.array_namespace(np.empty(0))
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
        return _NUMPY
    arrays = [v for v in values if v is not None and _is_array(v)]
    if not arrays:
        return _NUMPY
    return array_api_compat.array_namespace(*arrays)


def as_float(value: object, xp: Any) -> Array:
    """``value`` as a floating array of namespace ``xp`` (float64 for non-float input).

    A pint ``Quantity`` becomes its magnitude in SI base units (see the module docstring).
    """
    if type(value) is np.ndarray and xp is _NUMPY and value.dtype == np.float64:
        return value
    if is_quantity(value):
        value = si_magnitude(value)
    if _is_array(value):
        dtype = getattr(value, "dtype", None)
        if dtype is not None and xp.isdtype(dtype, "real floating"):
            return value
        return xp.astype(value, xp.float64)
    if xp is _NUMPY:
        return np.asarray(value, dtype=np.float64)
    return xp.asarray(value, dtype=xp.float64)


def arrays(*values: object) -> tuple[Any, list[Array]]:
    """The common namespace and each value as a floating array of it.

    pint quantities are first replaced by their SI magnitudes, whose arrays fix the namespace.
    """
    if not all(type(v) in _PLAIN for v in values):
        values = tuple(si_magnitude(v) if is_quantity(v) else v for v in values)
    xp = namespace(*values)
    return xp, [as_float(v, xp) for v in values]


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
    """Raise ``ValueError`` unless every non-NaN element is finite (a scalar NaN also raises)."""
    valid = f"finite{' [' + unit + ']' if unit else ''}"
    _check_scalar_nan(name, value, xp, valid)
    if is_traced(value):
        return
    mask = xp.isinf(value)
    if any_known(mask, xp):
        raise ValueError(f"{name} must be {valid}, got {_describe(value, xp, mask)}")
