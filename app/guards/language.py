"""Each browser reads the app in its own language: its messages translated on their way to it.

The app builds one panel in English (the catalogs' message ids). viser sends each browser two streams, the
shared broadcast and the browser's own; both pass through ``viser.infra._infra._message_producer``, which
this wraps: a browser whose language is not English gets each text-bearing message (a control's label,
hint, options, a Markdown or Html element's content, a notification, a modal's title, a plot's title and
series) as a translated copy, made once per language and message and kept as long as the message lives, so
a hundred followers reading Spanish cost one translation and one serialization. A frame's poses and
points pass untouched after one type lookup. A dropdown's options are translated, so the value a browser
sends back is read back into English (:func:`app.language.words.english_option`, in
:mod:`app.guards.inputs`).
"""

from __future__ import annotations

import dataclasses
import html
import json
import threading
import weakref
from collections import OrderedDict
from collections.abc import AsyncGenerator, Callable
from typing import Any

import viser
from viser import _messages
from viser.infra import _infra

from app.contracts import ClientId
from app.guards.responses import request_headers
from app.language.catalogs import PSEUDO, SOURCE, check_language, negotiate
from app.language.words import translate

__all__ = ["LANG_MARKER", "Languages", "lang_marker", "recording_in"]

LANG_MARKER = '<span hidden data-rbl-lang="en"></span>'
"""An Html element's content that each browser receives naming its own language: the page's script sets
``<html lang>`` from it (:mod:`app.panel.access`), so a screen reader pronounces the page right."""


def lang_marker(lang: str, words: tuple[str, ...] = ()) -> str:
    """:data:`LANG_MARKER` as a browser reading ``lang`` receives it: its language, and the translations of
    ``words`` (what the page's own script writes or looks for, ``app.panel.access.PAGE_WORDS``) as JSON."""
    lang = check_language(lang)
    said = {word: translate(word, lang) for word in words if translate(word, lang) != word}
    extra = f" data-rbl-words='{html.escape(json.dumps(said, ensure_ascii=False))}'" if said else ""
    return LANG_MARKER.replace('"en"', f'"{lang}"' + extra)


_TEXT = frozenset(
    {"label", "hint", "content", "_markdown", "options", "title", "body", "_tab_labels", "_marks", "text"}
)
"""Props and updates that hold words (a dropdown's ``value`` too, see :data:`_CHOICES`; ``text``: a label's in
the 3D scene, such as "centre of mass")."""
_CHOICES = (_messages.GuiDropdownMessage, _messages.GuiButtonGroupMessage)
_WORDY: set[type] = set()
"""Message types that may carry words, learnt as they come; read and added to on viser's loop only."""
_PLAIN: set[type] = set()
"""Message types with no words (poses, points, meshes), learnt as they come; read on viser's loop only."""


class _Copies(weakref.ref):  # type: ignore[type-arg]
    """A weak reference to a message carrying its translated copies by language."""

    __slots__ = ("by_lang", "key")
    by_lang: dict[str, Any]
    key: int


class Languages:
    """The language of every browser of one viser server, and its messages translated for it.

    Parameters
    ----------
    server : viser.ViserServer
        Installed before any browser connects.
    default : str
        The language of a browser that has not chosen one (``rigid-body-lab --lang``).
    page_words : tuple of str
        What the page's own script writes or looks for (``app.panel.access.PAGE_WORDS``), sent translated in
        each browser's language marker (:func:`lang_marker`).

    Attributes
    ----------
    identity : callable(client_id) -> str or None, or None
        Names the browser a client is (``app.teaching.voters.Voters.browser``: its cookie; None for a
        client without one), so that a choice is remembered when the page is loaded again.
    """

    REMEMBERED = 10_000
    """Browsers whose choice is remembered (the newest)."""

    def __init__(self, server: viser.ViserServer, default: str = SOURCE, page_words: tuple[str, ...] = ()) -> None:
        self.default = check_language(default)
        self.page_words = tuple(page_words)
        self.identity: Callable[[ClientId], str | None] | None = None
        self._server = server
        self._langs: dict[ClientId, str] = {}
        self._chosen: OrderedDict[str, str] = OrderedDict()  # a browser's identity -> its choice
        self._choices: set[str] = set()  # uuids of dropdowns and button groups
        self._texts: set[str] = set()  # uuids of text boxes
        self._readouts: set[str] = set()  # uuids of text boxes shown disabled: a readout, whose value is words
        self._copies: dict[int, _Copies] = {}
        self._lock = threading.Lock()
        self._install()

    # ------------------------------------------------------------------ asked from any thread
    def language(self, client_id: ClientId) -> str:
        """The language a browser reads: chosen, or else the one its ``Accept-Language`` prefers among ours,
        or else :attr:`default` (decided as its first message is sent, before viser's connect callbacks,
        which run later on a thread)."""
        lang = self._langs.get(client_id)  # one dict read: atomic, and asked for every message
        if lang is None:
            lang = self._remembered(client_id) or self._preferred(client_id)
            with self._lock:
                lang = self._langs.setdefault(client_id, lang)
        return lang

    def _remembered(self, client_id: ClientId) -> str | None:
        who = self.identity(client_id) if self.identity is not None else None
        with self._lock:
            return self._chosen.get(who) if who is not None else None

    def _preferred(self, client_id: ClientId) -> str:
        if self.default == PSEUDO:  # a translator's or a test's server: every page shows what is left
            return PSEUDO
        headers = request_headers(self._server, client_id)
        preferred = None if headers is None else headers.get("Accept-Language")
        return negotiate(preferred if isinstance(preferred, str) else None, self.default)

    def choose(self, client_id: ClientId, lang: str) -> None:
        """A browser reads ``lang`` from now on (ValueError for a language the app does not speak)."""
        lang = check_language(lang)
        who = self.identity(client_id) if self.identity is not None else None
        with self._lock:
            self._langs[client_id] = lang
            if who is not None:  # a browser with a cookie: its next page too
                self._chosen[who] = lang
                self._chosen.move_to_end(who)
                while len(self._chosen) > self.REMEMBERED:
                    self._chosen.popitem(last=False)

    def forget(self, client_id: ClientId) -> None:
        """The browser has gone."""
        with self._lock:
            self._langs.pop(client_id, None)

    def words(self, client_id: ClientId) -> list[Any]:
        """Messages that re-send every word of the panel (shared and the browser's own), in English: sent to
        this browser alone after it chose a language, they arrive translated."""
        out: list[Any] = []
        guis: list[Any] = [self._server.gui]
        client = self._server.get_clients().get(client_id)
        if client is not None:
            guis.append(client.gui)
        handles: dict[str, Any] = {}
        for gui in guis:  # every element sits in a container's children (folders, tabs and the root)
            for container in list(gui._container_handle_from_uuid.values()):
                handles.update(getattr(container, "_children", {}))
        for uuid, handle in handles.items():
            impl = getattr(handle, "_impl", None)
            if impl is None or impl.removed:
                continue
            props = impl.props
            updates = {k: getattr(props, k) for k in _TEXT if hasattr(props, k) and getattr(props, k) is not None}
            if (uuid in self._choices or uuid in self._readouts) and hasattr(impl, "value"):
                updates["value"] = impl.value
            if updates:
                out.append(_messages.GuiUpdateMessage(uuid, updates))
        return out

    def resend(self, client: viser.ClientHandle) -> None:
        """Send this browser every word of its panel again (it has chosen another language)."""
        for message in self.words(client.client_id):
            client._websock_connection.queue_message(message)

    # ------------------------------------------------------------------ on viser's event loop
    def _install(self) -> None:
        _install_producer()
        _SERVED.add(self)

    def serves(self, buffer: Any, client_id: ClientId) -> bool:
        """Whether ``buffer`` is this server's broadcast or the browser ``client_id``'s own buffer."""
        websock = self._server._websock_server
        if buffer is websock._broadcast_buffer:
            return True
        state = websock._client_state_from_id.get(client_id)
        return state is not None and state.message_buffer is buffer

    def translated(self, message: Any, client_id: ClientId) -> Any:
        """``message`` as the browser ``client_id`` reads it."""
        kind = type(message)
        if kind in _PLAIN:  # a frame's poses: most of the stream, one lookup whatever the language
            return message
        if kind is _messages.GuiRemoveMessage:  # an element gone: forgotten (it carries no words)
            self._choices.discard(message.uuid)
            self._texts.discard(message.uuid)
            self._readouts.discard(message.uuid)
            return message
        if kind not in _WORDY:
            if not dataclasses.is_dataclass(message) or not any(
                _has_words(f.name) for f in dataclasses.fields(message)
            ):
                _PLAIN.add(kind)
                return message
            _WORDY.add(kind)
        if isinstance(message, _messages.GuiTextMessage):
            self._texts.add(message.uuid)
            (self._readouts.add if message.props.disabled else self._readouts.discard)(message.uuid)
        elif isinstance(message, _messages.GuiUpdateMessage) and message.uuid in self._texts:
            if "disabled" in message.updates:  # a box made editable is a student's text: never translated
                (self._readouts.add if message.updates["disabled"] else self._readouts.discard)(message.uuid)
        elif isinstance(message, _CHOICES):
            self._choices.add(message.uuid)
        lang = self.language(client_id)
        if lang == SOURCE:
            return message
        key = id(message)
        copies = self._copies.get(key)
        if copies is None or copies() is not message:
            copies = _Copies(message, self._drop)
            copies.by_lang, copies.key = {}, key
            self._copies[key] = copies
        copy = copies.by_lang.get(lang)
        if copy is None:
            copy = copies.by_lang[lang] = self._translate(message, lang)
        return copy

    def _drop(self, copies: _Copies) -> None:
        if self._copies.get(copies.key) is copies:
            del self._copies[copies.key]

    def _translate(self, message: Any, lang: str) -> Any:
        if isinstance(message, _messages.GuiUpdateMessage):
            choice = message.uuid in self._choices or message.uuid in self._readouts
            updates = {
                k: _words(v, lang, self.page_words) if k in _TEXT or (choice and k == "value") else v
                for k, v in message.updates.items()
            }
            return _messages.GuiUpdateMessage(message.uuid, updates)
        changes: dict[str, Any] = {}
        for field in dataclasses.fields(message):
            value = getattr(message, field.name)
            if field.name == "props" and dataclasses.is_dataclass(value):
                changes["props"] = _translated_props(value, lang, self.page_words)
            elif field.name in _TEXT or (field.name == "value" and self._valued(message)):
                changes[field.name] = _words(value, lang, self.page_words)
        if all(changes[name] is getattr(message, name) for name in changes):
            return message
        return dataclasses.replace(message, **changes)

    def _valued(self, message: Any) -> bool:
        """Whether a control's value is words: a dropdown's option, a readout's text."""
        return isinstance(message, _CHOICES) or message.uuid in self._readouts


def _has_words(field: str) -> bool:
    return field in _TEXT or field in ("props", "updates")


def _translated_props(props: Any, lang: str, page_words: tuple[str, ...]) -> Any:
    changes = {}
    for field in dataclasses.fields(props):
        value = getattr(props, field.name)
        if field.name in _TEXT:
            changes[field.name] = _words(value, lang, page_words)
        elif field.name in ("series", "axes") and isinstance(value, tuple):
            changes[field.name] = tuple(
                _words(part, lang, page_words) if isinstance(part, dict) else part for part in value
            )
    return dataclasses.replace(props, **changes) if changes else props


def _words(value: Any, lang: str, page_words: tuple[str, ...]) -> Any:
    """A prop's value with its words translated: a text, a tuple of texts, a plot series' ``label``; the
    language marker made for ``lang`` (with ``page_words``)."""
    if isinstance(value, str):
        if value == LANG_MARKER:
            return lang_marker(lang, page_words)
        return translate(value, lang)
    if isinstance(value, tuple):
        return tuple(_words(v, lang, page_words) for v in value)
    if isinstance(value, dict) and isinstance(value.get("label"), str):
        return {**value, "label": translate(value["label"], lang)}
    label = getattr(value, "label", None)
    if dataclasses.is_dataclass(value) and not isinstance(value, type) and isinstance(label, str):
        return dataclasses.replace(value, label=translate(label, lang))  # a slider's mark
    return value


def recording_in(serializer: Any, lang: str) -> None:
    """Translate, in place, the words of a recording (``viser.ViserServer.get_scene_serializer``, before its
    ``as_html``) for readers of ``lang``: the 3D scene's labels, as a browser reading ``lang`` sees them
    live (an export's page, ``rigid-body-lab export --lang``). The recording holds serialized messages
    (dicts), whose words sit in the fields, props and updates named in :data:`_TEXT`."""
    lang = check_language(lang)
    if lang == SOURCE:
        return
    recorded = serializer._messages
    for index, (moment, message) in enumerate(recorded):
        changed = _dict_words(message, lang)
        for part in ("props", "updates"):
            if isinstance(message.get(part), dict):
                inner = _dict_words(message[part], lang)
                if inner is not message[part]:
                    changed = {**changed, part: inner}
        if changed is not message:
            recorded[index] = (moment, changed)


def _dict_words(fields: dict[str, Any], lang: str) -> dict[str, Any]:
    """``fields`` with the values of its word-bearing keys translated (itself if none changed)."""
    changes = {}
    for key in _TEXT.intersection(fields):
        value = fields[key]
        words = [translate(v, lang) if isinstance(v, str) else v for v in value] if isinstance(value, list) else None
        now = words if words is not None else _words(value, lang, ())
        if now != value:
            changes[key] = now
    return {**fields, **changes} if changes else fields


_SERVED: weakref.WeakSet[Languages] = weakref.WeakSet()
"""Every server's languages in this process (tests run many servers; viser's producer is one function)."""


def _install_producer() -> None:
    """Wrap viser's producer once per process: each browser's buffers are read through its server's
    :class:`Languages`."""
    original = _infra._message_producer
    if getattr(original, "rbl_languages", False):
        return

    async def producer(websocket: Any, buffer: Any, client_id: int, **kwargs: Any) -> None:
        for languages in list(_SERVED):
            if languages.serves(buffer, client_id):
                buffer = _Translating(buffer, languages.translated)
                break
        await original(websocket, buffer, client_id, **kwargs)

    producer.rbl_languages = True  # type: ignore[attr-defined]
    _infra._message_producer = producer  # type: ignore[assignment]


class _Translating:
    """One of viser's message buffers as one browser's producer reads it: each window translated."""

    def __init__(self, buffer: Any, translated: Callable[[Any, ClientId], Any]) -> None:
        self._buffer, self._translated = buffer, translated

    @property
    def done(self) -> bool:
        return bool(self._buffer.done)

    def window_generator(self, client_id: ClientId, backlog_done_message: Any = None) -> AsyncGenerator[Any, None]:
        inner = self._buffer.window_generator(client_id, backlog_done_message=backlog_done_message)
        return self._windows(inner, client_id)

    async def _windows(self, inner: Any, client_id: ClientId) -> AsyncGenerator[Any, None]:
        translated = self._translated
        try:
            async for window in inner:
                yield [translated(m, client_id) for m in window]
        finally:
            await inner.aclose()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._buffer, name)
