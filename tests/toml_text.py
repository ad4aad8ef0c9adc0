"""Scenario documents as TOML text, for tests that write scenario files.

``tomllib`` reads TOML but does not write it; the tests that break one value of a scenario
(the bad-input catalogue, the fuzzer) write their documents with :func:`toml_dumps`.
"""

import datetime
import json
import math
import re
from typing import Any


class Raw(str):
    """TOML text written as it is (a literal such as ``1e400`` or a datetime)."""


def toml_value(value: Any) -> str:
    if isinstance(value, Raw):
        return str(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        text = repr(value)
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, datetime.datetime | datetime.date | datetime.time):
        return value.isoformat()
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{toml_key(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no TOML for {value!r}")


def toml_key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key, ensure_ascii=False)


def toml_dumps(document: dict[str, Any]) -> str:
    """A document as TOML: every top-level key with an inline value."""
    return "".join(f"{toml_key(k)} = {toml_value(v)}\n" for k, v in document.items())
