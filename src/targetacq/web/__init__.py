"""The local web explorer: a JSON API over the library and the page that uses it.

:func:`create_app` builds the FastAPI application (:mod:`targetacq.web.api`); ``targetacq
serve`` runs it with uvicorn. FastAPI and uvicorn are the ``web`` extra
(``pip install 'targetacq[web]'``): they are imported only when the application is built, so
``import targetacq`` never needs them.
"""

from __future__ import annotations

import importlib.util
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from targetacq.web.api import create_app

__all__ = ["WEB_EXTRA", "create_app", "require_web"]

WEB_EXTRA = "pip install 'targetacq[web]'"
"""How to install what the explorer needs."""


def require_web(*modules: str) -> None:
    """Check that the web extra's packages are installed.

    Parameters
    ----------
    *modules : str
        Module names to check (default ``fastapi``).

    Raises
    ------
    ModuleNotFoundError
        Naming the missing package and the ``web`` extra that installs it.
    """
    for module in modules or ("fastapi",):
        if importlib.util.find_spec(module) is None:
            raise ModuleNotFoundError(
                f"the web explorer needs {module}, which is not installed: {WEB_EXTRA}",
                name=module,
            )


def __getattr__(name: str) -> Any:
    if name == "create_app":
        require_web("fastapi")
        from targetacq.web.api import create_app

        return create_app
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
