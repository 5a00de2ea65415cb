"""viser's public share tunnel, opened only when the server was started with ``--share``.

Hiding viser's share button is not enough: viser 1.1.1 opens a public tunnel for a ``ShareUrlRequest`` from
*any* websocket client. :func:`guard_tunnel` replaces its two handlers: without ``--share`` both are refused;
with it, only a browser that may drive the simulation opens or closes the tunnel.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser
from viser import _messages

from app.contracts import ClientId

__all__ = ["NOT_SHARED", "guard_tunnel"]

NOT_SHARED = "This server is not published on a public tunnel. Start it with --share to allow one."
"""What a browser is told when it asks for a tunnel the lecturer did not allow."""


def guard_tunnel(
    server: viser.ViserServer,
    *,
    share: bool,
    refuse: Callable[[Any, str], None],
    permit: Callable[[Any], str | None] | None = None,
) -> None:
    """Put our check in place of viser's handlers for a public share tunnel.

    Parameters
    ----------
    server : viser.ViserServer
        The server whose tunnel handlers are replaced (once, at start).
    share : bool
        True if the server was started with ``--share``; without it every request is refused.
    refuse : callable(client_id, reason)
        Tells a refused browser why (one notification, to that browser alone).
    permit : callable(client_id) -> str or None, optional
        Whether a browser may drive the simulation: None if it may, otherwise the reason it may not.
        With ``share``, only such a browser opens or closes the tunnel.
    """
    interface = server._websock_server

    def handler(action: str) -> Callable[[Any, Any], None]:
        def run(client_id: ClientId, _message: Any) -> None:
            reason = NOT_SHARED if not share else (permit(client_id) if permit is not None else None)
            if reason is not None:
                refuse(client_id, reason)
                return
            # viser's request blocks on a network round trip: off the event loop, as viser itself does.
            server._thread_executor.submit(getattr(server, action))

        return run

    for message, action in (
        (_messages.ShareUrlRequest, "request_share_url"),
        (_messages.ShareUrlDisconnect, "disconnect_share_url"),
    ):
        interface.unregister_handler(message)  # viser's own, which asks no one
        interface.register_handler(message, handler(action))
