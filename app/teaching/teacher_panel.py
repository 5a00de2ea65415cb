"""The controls of the teacher's view of private sessions, in one browser's panel.

Every private session (``rigid-body-lab --private --pin PIN``) gets a "Your name" box, a "Teacher PIN"
box and an "Open teacher's view" button on top of its simulation's panel. A browser that opens the view
gets, instead of the PIN box, the table of sessions (one Html element, rewritten once a second), a
dropdown of the sessions' numbers and a Spotlight button. What they do is :mod:`app.teaching.teacher`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import viser

from app.language.words import mark, say

__all__ = ["NO_SESSION", "TeacherPanel"]

NO_SESSION = "—"
"""The dropdown's only choice while no student is connected."""

NAME_HINT = mark("Optional: shown to your teacher instead of your session's number.")

WATCHED = mark("your teacher can see this session's scene, settings and time.")
"""What every student is told: the teacher's table shows their session."""


class TeacherPanel:
    """One browser's controls for the teacher's view (created on its own ``client.gui``).

    Parameters
    ----------
    client : viser.ClientHandle
        The browser.
    number : int
        Its session's number, shown to it so that it can tell the teacher which one is its own.
    """

    def __init__(self, client: viser.ClientHandle, number: int) -> None:
        gui = client.gui
        self.gui = gui
        self.number = gui.add_markdown(
            say("**Session {number}** · {watched}", number=number, watched=WATCHED), order=-33
        )
        self.name = gui.add_text(mark("Your name"), initial_value="", hint=NAME_HINT, order=-32)
        self.pin: Any = gui.add_text(mark("Teacher PIN"), initial_value="", order=-31)
        self.open: Any = gui.add_button(mark("Open teacher's view"), order=-30)
        self.folder: Any = None
        self.table: Any = None
        self.choice: Any = None
        self.spotlight: viser.GuiButtonHandle | None = None

    @property
    def teaching(self) -> bool:
        """Whether this browser has the teacher's view."""
        return self.table is not None

    def show_view(self, table_html: str, numbers: Sequence[str]) -> viser.GuiButtonHandle:
        """Replace the PIN box by the teacher's view: the table, the sessions' numbers and Spotlight (returned)."""
        self.pin.remove()
        self.open.remove()
        self.folder = self.gui.add_folder(mark("Teacher's view"), order=-29)
        with self.folder:
            self.table = self.gui.add_html(table_html)
            self.choice = self.gui.add_dropdown(mark("Session"), tuple(numbers) or (NO_SESSION,))
            self.spotlight = self.gui.add_button(mark("Spotlight"))
        return self.spotlight

    def show_table(self, table_html: str) -> None:
        """Rewrite the table (one message to this browser, none if it did not change)."""
        if self.table is not None and self.table.content != table_html:
            self.table.content = table_html

    def show_numbers(self, numbers: Sequence[str]) -> None:
        """The dropdown's choices (the choice stays if its session is still there)."""
        options = tuple(numbers) or (NO_SESSION,)
        if self.choice is not None and tuple(self.choice.options) != options:
            self.choice.options = options
