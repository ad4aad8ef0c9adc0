"""The `serve` command: the local web explorer and its JSON API."""

from __future__ import annotations

import ipaddress
import socket
import sys
from typing import Annotated

import typer

from targetacq.cli import app

DEFAULT_HOST = "127.0.0.1"
"""Loopback: the explorer is reachable from this machine only unless --host says otherwise."""

DEFAULT_PORT = 8050


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine only (``localhost``, 127.0.0.0/8, ``::1``).

    Examples
    --------
    >>> is_loopback("127.0.0.1"), is_loopback("localhost"), is_loopback("0.0.0.0")
    (True, True, False)
    """
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def listening_socket(host: str, port: int) -> socket.socket:
    """A TCP socket bound to ``host``:``port`` and listening.

    Raises
    ------
    ValueError
        If the address cannot be resolved or bound (a port in use, a port below 1024 without
        the right), naming the address and the reason.
    """
    where = f"{host}:{port}"
    try:
        infos = socket.getaddrinfo(host.strip("[]"), port, type=socket.SOCK_STREAM)
    except (OSError, UnicodeError) as error:
        reason = getattr(error, "strerror", None) or error
        raise ValueError(f"cannot listen on {where}: {reason}") from None
    family, kind, proto, _, address = infos[0]
    sock = socket.socket(family, kind, proto)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(address)
        sock.listen(128)
    except OSError as error:
        sock.close()
        raise ValueError(f"cannot listen on {where}: {error.strerror or error}") from None
    return sock


@app.command("serve")
def serve(
    host: Annotated[
        str,
        typer.Option(help="Address to listen on; other than loopback, the network can reach it."),
    ] = DEFAULT_HOST,
    port: Annotated[
        int, typer.Option(min=0, max=65535, help="Port to listen on (0: any free port).")
    ] = DEFAULT_PORT,
) -> None:
    """Run the local web explorer and its JSON API (uvicorn) until interrupted (Ctrl-C).

    The page is at http://HOST:PORT/, the API's interactive documentation at /docs and its
    schema at /openapi.json. Loopback (127.0.0.1) by default: only this machine can reach it.

    Example: targetacq serve --port 8050
    """
    from targetacq.web import require_web

    try:
        require_web("fastapi", "uvicorn")
    except ModuleNotFoundError as error:
        raise ValueError(str(error)) from None
    import uvicorn

    from targetacq.web.api import create_app

    sock = listening_socket(host, port)
    bound_port = sock.getsockname()[1]
    shown = f"[{host}]" if ":" in host and not host.startswith("[") else host
    typer.echo(f"targetacq explorer on http://{shown}:{bound_port}/ (API docs: /docs)")
    if not is_loopback(host):
        sys.stderr.write(
            f"targetacq: warning: listening on {host}, not loopback: the explorer is reachable "
            "from the network (it has no authentication)\n"
        )
    sys.stdout.flush()
    sys.stderr.flush()
    # Bound to loopback, only requests addressed to loopback names are answered: a web page
    # elsewhere cannot reach the server through a name it re-points at 127.0.0.1.
    trusted = ["127.0.0.1", "localhost", "::1", "[::1]"] if is_loopback(host) else None
    config = uvicorn.Config(create_app(trusted_hosts=trusted), log_level="warning")
    try:
        uvicorn.Server(config).run(sockets=[sock])
    finally:
        sock.close()
