"""viser's public share tunnel, opened only when the server was started with ``--share``.

Hiding viser's share button (``configure_theme(show_share_button=False)``, :mod:`app.look`) is not
enough: viser 1.1.1 answers a ``ShareUrlRequest`` message from *any* websocket client by opening a
public tunnel to this server, and a ``ShareUrlDisconnect`` by closing it. A page without the button, a
follower without the presenter PIN or a script could still publish a lecture held on 127.0.0.1.

:func:`guard_tunnel` replaces viser's two handlers. Without ``--share`` both are refused; with it, only a
browser that may drive the simulation (everyone in shared and private mode, the presenter in presenter
mode) may open or close the tunnel. A refusal goes to that browser alone, as one notification.

This replaces a private piece of viser 1.1.1 (its handler lists for the two messages); viser is pinned,
and ``tests/app/test_tunnel.py`` sends the messages through a real websocket to prove it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser
from viser import _messages

__all__ = ["NOT_SHARED", "guard_tunnel"]

NOT_SHARED = "This server is not published on a public tunnel. Start it with --share to allow one."
"""What a browser is told when it asks for a tunnel the lecturer did not allow."""

NOTIFY_SECONDS = 6.0  # as app.server.NOTIFY_SECONDS (not imported: the server imports this module)


def guard_tunnel(server: viser.ViserServer, *, share: bool, permit: Callable[[Any], str | None] | None = None) -> None:
    """Put our check in place of viser's handlers for a public share tunnel.

    Parameters
    ----------
    server : viser.ViserServer
        The server whose tunnel handlers are replaced (once, at start).
    share : bool
        True if the server was started with ``--share``; without it every request is refused.
    permit : callable(client_id) -> str or None, optional
        Whether a browser may drive the simulation: None if it may, otherwise the reason it may not.
        With ``share``, only such a browser opens or closes the tunnel.
    """
    interface = server._websock_server

    def refuse(client_id: Any, reason: str) -> None:
        client = server.get_clients().get(client_id)
        if client is None:
            return
        try:
            client.add_notification("Refused", reason, color="red", auto_close_seconds=NOTIFY_SECONDS)
        except Exception:  # noqa: BLE001 - a browser that just left must not break viser's event loop
            pass

    def handler(action: str) -> Callable[[Any, Any], None]:
        def run(client_id: Any, _message: Any) -> None:
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
