"""HTTP requests and responses of viser 1.1.1's websockets server, which viser offers no hook for.

Class questions (:mod:`app.teaching.voters`) set a cookie on the page a browser loads and read it back from
the request that opened a browser's websocket. Both reach into viser's private server, so they live here.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

import viser

__all__ = ["hook_responses", "request_headers"]


def request_headers(server: viser.ViserServer, client_id: int) -> Any:
    """The HTTP headers (a ``websockets`` ``Headers``, read like a dict) of the request that opened client
    ``client_id``'s websocket; None for a client that is not connected."""
    connection = server._websock_server._live_connections.get(client_id)
    request = getattr(connection, "request", None)
    return None if request is None else request.headers


def hook_responses(server: viser.ViserServer, respond: Callable[[Any, Any, Any], Any]) -> bool:
    """Set ``respond(connection, request, response) -> response`` as the ``process_response`` of viser's
    websockets server (it sees every HTTP response, the page's included); False if it cannot be found."""
    loop = server._websock_server._background_event_loop
    if loop is None:
        return False

    async def find() -> bool:
        for task in asyncio.all_tasks():
            frame = getattr(task.get_coro(), "cr_frame", None)
            serving = frame.f_locals.get("serve_future") if frame is not None else None  # websockets' Server
            if serving is not None and hasattr(serving, "process_response"):
                serving.process_response = respond
                return True
        return False

    try:
        return bool(asyncio.run_coroutine_threadsafe(find(), loop).result(timeout=10.0))
    except Exception:  # noqa: BLE001 - a server that is stopping: no hook
        return False
