"""Who is voting, without a name: one identity per browser, kept across its reconnects.

The server hands every browser that loads the page a random token in an HttpOnly cookie
(:data:`COOKIE`); the browser sends it back when its page opens the websocket, and the token is the
browser's identity for class questions (:mod:`app.teaching.questions`). A copy of the page in the same
browser, or the same page after a reconnect, has the same identity and so the same single answer. A
client that brings no token the server issued (a script's raw websocket) is one voter per connection.
The token says nothing about the student: no name is asked or kept.

viser 1.1.1 has no hook for its HTTP responses: :func:`app.guards.responses.hook_responses` sets one.
More in docs/app-notes.md (``app.teaching.voters``).
"""

from __future__ import annotations

import secrets
import threading
from collections import OrderedDict
from http.cookies import CookieError, SimpleCookie
from typing import Any

import viser

from app.contracts import ClientId
from app.guards.responses import hook_responses, request_headers

__all__ = ["COOKIE", "MAX_TOKENS", "Voters"]

COOKIE = "rbl_voter"
"""Name of the cookie that carries a browser's voter token."""

MAX_TOKENS = 100_000
"""Tokens remembered; the oldest are forgotten past this (their browsers then vote per connection)."""


class Voters:
    """The voter identity of every browser of one viser server.

    Parameters
    ----------
    server : viser.ViserServer
        A running server: the cookie is set on the pages it serves from now on.
    """

    def __init__(self, server: viser.ViserServer) -> None:
        self._server = server
        self._tokens: OrderedDict[str, None] = OrderedDict()
        self._lock = threading.Lock()
        self.installed = hook_responses(server, self._respond)

    def issue(self) -> str:
        """A new token, remembered (what a page served now receives)."""
        token = secrets.token_urlsafe(18)
        with self._lock:
            self._tokens[token] = None
            while len(self._tokens) > MAX_TOKENS:
                self._tokens.popitem(last=False)
        return token

    def known(self, token: str | None) -> bool:
        with self._lock:
            return token is not None and token in self._tokens

    def identity(self, client_id: ClientId) -> str:
        """The voter a connected client counts as: its browser's token, or its connection alone."""
        return self.browser(client_id) or f"connection {client_id}"

    def browser(self, client_id: ClientId) -> str | None:
        """The browser a connected client is (its token), or None if it came without a known token."""
        headers = request_headers(self._server, client_id)
        token = _token(headers.get("Cookie")) if headers is not None else None
        return f"browser {token}" if self.known(token) else None

    def _respond(self, connection: Any, request: Any, response: Any) -> Any:
        """websockets' process_response: a page served to a browser without a known token sets one."""
        if request.headers.get("Upgrade") == "websocket" or response.status_code != 200:
            return response
        if not self.known(_token(request.headers.get("Cookie"))):
            response.headers["Set-Cookie"] = f"{COOKIE}={self.issue()}; Path=/; HttpOnly; SameSite=Strict"
        return response


def _token(header: str | None) -> str | None:
    if not header:
        return None
    jar: SimpleCookie = SimpleCookie()
    try:
        jar.load(header)
    except CookieError:
        return None
    morsel = jar.get(COOKIE)
    return None if morsel is None else morsel.value
