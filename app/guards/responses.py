"""HTTP requests and responses of viser 1.1.1's websockets server, which viser offers no hook for.

Class questions (:mod:`app.teaching.voters`) set a cookie on the page a browser loads and read it back from
the request that opened a browser's websocket. Both reach into viser's private server, so they live here.
"""

from __future__ import annotations

import asyncio
import http
import inspect
from collections.abc import Callable
from typing import Any

import viser
from websockets.asyncio.server import Server, ServerConnection
from websockets.http11 import Request

from app.language.catalogs import SOURCE, negotiate
from app.language.words import translate

__all__ = ["connection_address", "hook_requests", "hook_responses", "peer_address", "request_headers", "user_agent"]


def request_headers(server: viser.ViserServer, client_id: int) -> Any:
    """The HTTP headers (a ``websockets`` ``Headers``, read like a dict) of the request that opened client
    ``client_id``'s websocket; None for a client that is not connected."""
    connection = server._websock_server._live_connections.get(client_id)
    request = getattr(connection, "request", None)
    return None if request is None else request.headers


def user_agent(client: viser.ClientHandle) -> str:
    """The ``User-Agent`` of the request that opened a browser's websocket (``client``: a viser
    ``ClientHandle``); empty when unknown."""
    server = getattr(client, "_viser_server", None)
    headers = None if server is None else request_headers(server, client.client_id)
    return "" if headers is None else str(headers.get("User-Agent", ""))


def peer_address(server: viser.ViserServer, client_id: int) -> str | None:
    """The network address client ``client_id`` connects from (None for a client that is not connected).

    Behind the rooms' proxy (:mod:`app.rooms.nginx`) every websocket comes from a loopback address and the
    proxy names the browser's in ``X-Real-IP``; that header is believed only from a loopback peer (a browser
    elsewhere could write any address into it).
    """
    connection = server._websock_server._live_connections.get(client_id)
    return None if connection is None else connection_address(connection)


def connection_address(connection: ServerConnection) -> str:
    """The address of a websockets ``ServerConnection`` (see :func:`peer_address`)."""
    remote = getattr(connection, "remote_address", None)
    host = str(remote[0]) if remote else "unknown"
    if host.startswith("::ffff:"):
        host = host[len("::ffff:") :]
    if host == "::1" or host.startswith("127."):
        request = getattr(connection, "request", None)
        forwarded = request.headers.get("X-Real-IP") if request is not None else None
        if forwarded and len(forwarded) <= 64:
            return str(forwarded).strip()
    return host


def hook_responses(server: viser.ViserServer, respond: Callable[[Any, Any, Any], Any]) -> bool:
    """Set ``respond(connection, request, response) -> response`` as the ``process_response`` of viser's
    websockets server (it sees every HTTP response, the page's included); False if it cannot be found."""

    def install(serving: Server) -> None:
        serving.process_response = respond

    return _on_serving(server, install, "process_response")


def hook_requests(
    server: viser.ViserServer, turn_away: Callable[[str], str | None], hold: float = 0.0, most_held: int = 0
) -> bool:
    """Before a websocket opens, ask ``turn_away(address)`` (the browser's address, as
    :func:`connection_address` reads it) and answer 429 with its reason, not a websocket, when it gives one:
    no upgrade, no handler, no close handshake (an address that keeps reconnecting costs the server a parsed
    request each time, not a connection). The answer is held back ``hold`` seconds (at most ``most_held``
    answers at once, the rest answered at once): a script that reconnects as soon as it is answered then
    costs a parsed request a second, not hundreds, and a page that retries learns why a second later. Every
    other request goes to viser's own handler (its page and files). False if viser's server cannot be found."""
    held = [0]  # answers being held back now (read and changed on viser's event loop only)

    def install(serving: Server) -> None:
        original = serving.process_request

        async def process_request(connection: ServerConnection, request: Request) -> Any:
            if str(request.headers.get("Upgrade", "")).lower() == "websocket":
                reason = turn_away(connection_address(connection))  # (the request is on the connection now)
                if reason is not None:
                    lang = negotiate(request.headers.get("Accept-Language"), SOURCE)
                    if hold > 0.0 and held[0] < most_held:
                        held[0] += 1
                        try:
                            await asyncio.sleep(hold)
                        finally:
                            held[0] -= 1
                    return connection.respond(http.HTTPStatus.TOO_MANY_REQUESTS, translate(reason, lang) + "\n")
            if original is None:
                return None
            response = original(connection, request)
            return await response if inspect.isawaitable(response) else response

        serving.process_request = process_request

    return _on_serving(server, install, "process_request")


def _on_serving(server: viser.ViserServer, install: Callable[[Server], None], attribute: str) -> bool:
    """Run ``install(serving)`` on viser's websockets ``Server`` (found among the event loop's tasks, as
    one with ``attribute``) in its event loop; False if it cannot be found."""
    loop = server._websock_server._background_event_loop
    if loop is None:
        return False

    async def find() -> bool:
        for task in asyncio.all_tasks():
            frame = getattr(task.get_coro(), "cr_frame", None)
            serving = frame.f_locals.get("serve_future") if frame is not None else None  # websockets' Server
            if serving is not None and hasattr(serving, attribute):
                install(serving)
                return True
        return False

    try:
        return bool(asyncio.run_coroutine_threadsafe(find(), loop).result(timeout=10.0))
    except Exception:  # noqa: BLE001 - a server that is stopping: no hook
        return False
