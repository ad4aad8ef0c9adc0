"""Looking names up in the registries (criteria, transforms, noise models, obscurants, ...).

Every registry is a read-only mapping of names; this is the one place that turns an unknown
name into the error a user sees: the name, a "did you mean" when one is close, and the valid
names.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from difflib import get_close_matches
from typing import Any, TypeVar

__all__ = ["lookup", "unknown_name"]

T = TypeVar("T")


def unknown_name(name: str, valid: Sequence[str], kind: str) -> ValueError:
    """The error for an unknown name of a kind, listing the valid names."""
    close = get_close_matches(name, list(valid), 1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return ValueError(f"unknown {kind} {name!r}{hint}; valid: {', '.join(valid)}")


def lookup(registry: Mapping[str, T], name: Any, kind: str) -> T:
    """``registry[name]``, or ``ValueError`` naming the kind, a close match and the valid names."""
    if not isinstance(name, str) or name not in registry:
        raise unknown_name(str(name), list(registry), kind)
    return registry[name]
