"""A browser's own choice of language: a dropdown in its panel, and the page's ``lang`` attribute.

Each browser has its own (``client.gui``), so a follower in presenter mode chooses too, and nobody else's
panel changes. The languages are named in themselves (Deutsch, Español, 中文), never translated.
"""

from __future__ import annotations

import viser

from app.guards.callbacks import shielded_handler
from app.guards.inputs import guard_inputs
from app.guards.language import LANG_MARKER, Languages
from app.language.catalogs import LANGUAGES, PSEUDO
from app.language.words import mark

__all__ = ["LanguagePicker", "PICKER_ORDER"]

PICKER_ORDER = 1e6 + 2.5
"""After the panel's Export folder, before its Keyboard folder (``app.panel.simulation_panel.LAST_ORDER`` + 2.5)."""


class LanguagePicker:
    """The Language dropdown of one browser, and the hidden element that names its language to the page.

    Parameters
    ----------
    client : viser.ClientHandle
        The browser.
    languages : Languages
        The server's languages (:class:`app.guards.language.Languages`); the browser's is already chosen.
    """

    def __init__(self, client: viser.ClientHandle, languages: Languages) -> None:
        self.client, self.languages = client, languages
        lang = languages.language(client.client_id)
        names = dict(LANGUAGES)
        if lang == PSEUDO:  # a translator's or a test's page: offered only where it was asked for
            names[PSEUDO] = PSEUDO
        self._codes = {name: code for code, name in names.items()}
        self.marker = client.gui.add_html(LANG_MARKER, order=PICKER_ORDER)
        self.dropdown = client.gui.add_dropdown(
            mark("Language"), options=tuple(names.values()), initial_value=names[lang], order=PICKER_ORDER
        )
        self.dropdown.on_update(shielded_handler(self._chosen, _tell))
        # The browser's own panel takes values as the shared one does: checked, refused to its sender.
        guard_inputs(client.gui, lambda _, reason: _tell(client, mark("Refused"), reason))

    def _chosen(self, _: object) -> None:
        code = self._codes.get(str(self.dropdown.value))
        if code is None or code == self.languages.language(self.client.client_id):
            return
        self.languages.choose(self.client.client_id, code)
        self.languages.resend(self.client)


def _tell(client: viser.ClientHandle | None, title: str, body: str) -> None:
    """A failed choice told to the browser that made it."""
    if client is not None:
        client.add_notification(title, body, color="red", auto_close_seconds=10.0)
