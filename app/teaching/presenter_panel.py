"""A browser's own controls in presenter mode (:mod:`app.teaching.presenter`): whether it follows the
lecturer, presents or explores a copy of its own, the presenter PIN box and the explore/follow button.
"""

from __future__ import annotations

import viser

from app.language.words import mark

__all__ = ["EXPLORING", "FOLLOWING", "PRESENTING", "PresenterPanel"]

FOLLOWING = mark("**Following the lecturer.** The panel below shows the lecture; enter the PIN to drive it.")
PRESENTING = mark("**Presenting.** Your changes are what the class sees.")
EXPLORING = mark("**Exploring on your own.** Nobody else sees this copy; the lecture goes on without you.")


class PresenterPanel:
    """One browser's own controls in presenter mode: its status, the PIN box and the explore/follow button."""

    def __init__(self, client: viser.ClientHandle) -> None:
        gui = client.gui
        self.status = gui.add_markdown(FOLLOWING, order=-30)
        self.pin = gui.add_text(mark("Presenter PIN"), initial_value="", order=-29)
        self.present = gui.add_button(mark("Present"), order=-28)
        self.explore = gui.add_button(mark("Explore on my own"), order=-27)

    def presenting(self) -> None:
        self.status.content = PRESENTING
        self.pin.remove()
        self.present.remove()
