"""A scene switch leaves no pose of the old scene in a browser that watched it.

The old scene's nodes are removed and the new scene's added, often under the same names. viser coalesces a
pending removal with a pending creation of the same name, so the browser sees a same-name creation, which
keeps the node's old pose (viser's client, ``SceneTreeState.ts``); a new node whose pose is the default
sends none. Here a websocket client follows every message as the page does (a removal forgets a node's
pose, a creation keeps what the name had, a pose message sets it) and, after each switch, every node of
the new scene must stand where the server put it.
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from tests.harness import raw_client, received, running_app

IDENTITY = (1.0, 0.0, 0.0, 0.0)
ORIGIN = (0.0, 0.0, 0.0)


class PageModel:
    """The poses a page holds, by node name, from the messages it received."""

    def __init__(self) -> None:
        self.poses: dict[str, dict[str, tuple[float, ...]]] = {}

    def take(self, messages: list[dict]) -> None:
        for m in messages:
            kind, name = m.get("type", ""), m.get("name")
            if name is None:
                continue
            if kind == "RemoveSceneNodeMessage":
                self.poses.pop(name, None)
            elif kind == "SetOrientationMessage":
                self.poses.setdefault(name, {"wxyz": IDENTITY, "position": ORIGIN})["wxyz"] = tuple(m["wxyz"])
            elif kind == "SetPositionMessage":
                self.poses.setdefault(name, {"wxyz": IDENTITY, "position": ORIGIN})["position"] = tuple(m["position"])
            elif "props" in m and kind.endswith("Message") and kind != "SceneNodeUpdateMessage":
                # A creation: a name the page already holds keeps its pose.
                self.poses.setdefault(name, {"wxyz": IDENTITY, "position": ORIGIN})


def _moved(page: PageModel) -> list[str]:
    return [n for n, p in page.poses.items() if n.startswith("/scene/") and p["wxyz"] != IDENTITY]


def _where_the_server_put_them(page: PageModel, app) -> bool:
    nodes = {n: h for n, h in app.server.scene._handle_from_node_name.items() if n.startswith("/scene")}
    return all(
        name in page.poses
        and np.allclose(page.poses[name]["wxyz"], handle.wxyz, rtol=0, atol=1e-12)
        and np.allclose(page.poses[name]["position"], handle.position, rtol=0, atol=1e-12)
        for name, handle in nodes.items()
    )


def _follow(ws, page: PageModel, done, timeout: float = 10.0) -> None:
    """The page takes what the server sends until ``done()`` (or ``timeout`` s), then 0.1 s more: every
    message was queued before the read, and a late one would still change what the checks see."""
    deadline = time.monotonic() + timeout
    while not done() and time.monotonic() < deadline:
        page.take(received(ws, 0.02))
    page.take(received(ws, 0.1))


@pytest.mark.parametrize(
    "old, new",
    [("wobble", "inertia_explorer"), ("wobble", "heavy_top"), ("free_fall", "pendulum"), ("tennis_racket", "wobble")],
)
def test_a_switch_leaves_no_old_pose_in_the_page(old: str, new: str) -> None:
    with running_app(old, start_loop=False) as app:
        with raw_client(app) as ws:
            page = PageModel()
            app.set_playing(True)
            for _ in range(30):  # half a second of the old scene: its nodes away from their defaults
                app.frame(1.0 / 60.0)
            _follow(ws, page, lambda: _moved(page))
            assert _moved(page), "the old scene turned nothing"
            app.switch_scene(new)
            app.frame(1.0 / 60.0)
            _follow(ws, page, lambda: _where_the_server_put_them(page, app))
            nodes = {n: h for n, h in app.server.scene._handle_from_node_name.items() if n.startswith("/scene")}
            assert nodes
            for name, handle in nodes.items():
                assert name in page.poses, name
                np.testing.assert_allclose(page.poses[name]["wxyz"], handle.wxyz, atol=1e-12, err_msg=name)
                np.testing.assert_allclose(page.poses[name]["position"], handle.position, atol=1e-12, err_msg=name)
