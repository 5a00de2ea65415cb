"""One wrapper for every callback a browser's message runs (a click, an upload, a vote): whatever it raises
never reaches viser's event loop, the simulation loop or another browser. The exception is printed for the
server's log and told to the browser that acted, as "Something went wrong"; if that browser has left
meanwhile, there is nobody to tell, and ``left`` may drop what was being made for it.
"""

from __future__ import annotations

import functools
import traceback
from collections.abc import Callable, Sequence
from typing import ParamSpec, TypeVar

import viser

from app.guards.wire import departed
from app.language.words import mark

__all__ = ["SOMETHING_WENT_WRONG", "event_client", "first_argument", "shielded", "shielded_handler"]

P = ParamSpec("P")
R = TypeVar("R")

SOMETHING_WENT_WRONG = mark("Something went wrong")
"""The title of the notification a failed callback sends to the browser that acted."""


def event_client(args: Sequence[object]) -> viser.ClientHandle | None:
    """The browser that acted, from a viser event (``event.client``) passed first; None without one."""
    client: viser.ClientHandle | None = getattr(args[0], "client", None) if args else None
    return client


def first_argument(args: Sequence[object]) -> viser.ClientHandle | None:
    """The browser that acted, passed itself as the first argument."""
    client: viser.ClientHandle | None = args[0] if args else None  # type: ignore[assignment]
    return client


def shielded(
    fn: Callable[P, R],
    tell: Callable[[viser.ClientHandle | None, str, str], None],
    *,
    client_of: Callable[[Sequence[object]], viser.ClientHandle | None] = event_client,
    left: Callable[[viser.ClientHandle], None] | None = None,
) -> Callable[P, R | None]:
    """``fn``, which returns None instead of raising.

    Parameters
    ----------
    fn : callable
        The callback.
    tell : callable(client, title, body)
        Tells the browser that acted (None: the callback had no browser) what went wrong.
    client_of : callable(args) -> client or None
        Finds the browser that acted among the callback's positional arguments (default: ``event.client``).
    left : callable(client), optional
        Called instead of ``tell`` when that browser has left while the callback ran.
    """

    @functools.wraps(fn)
    def run(*args: P.args, **kwargs: P.kwargs) -> R | None:
        try:
            return fn(*args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - told to the browser that acted, never raised into viser
            client = client_of(args)
            if client is not None and departed(client):
                if left is not None:
                    left(client)
                return None
            traceback.print_exc()
            tell(client, SOMETHING_WENT_WRONG, f"{type(exc).__name__}: {exc}")
            return None

    return run


E = TypeVar("E")


def shielded_handler(
    fn: Callable[[E], object],
    tell: Callable[[viser.ClientHandle | None, str, str], None],
    *,
    left: Callable[[viser.ClientHandle], None] | None = None,
) -> Callable[[E], None]:
    """:func:`shielded` for a viser event handler (``on_click``, ``on_update``): its result is dropped."""
    safe = shielded(fn, tell, left=left)

    def handle(event: E) -> None:
        safe(event)

    return handle
