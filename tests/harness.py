"""Shared helpers for the app's headless and browser tests (both app helpers use them).

* :func:`free_port` — a free TCP port on 127.0.0.1 (one per test server).
* :func:`running_app` — an :class:`app.server.App` on a free port, stopped afterwards.
* :func:`chromium_or_skip` — Debian's Chromium through Playwright's sync API, or a skip when it is
  missing; under ``RBL_REQUIRE_BROWSER=1`` (CI) a missing browser is a failure, never a skip.
* :func:`open_page` — load the app in a page and wait until the server sees the client and the
  3D canvas exists.
* :func:`wait_for` — poll a condition with a timeout (no fixed sleeps in tests).
* :func:`click` — click without waiting for a re-rendering element to be stable;
* :func:`slider_by_label` / :func:`nudge_slider` — drive a viser slider in the page with the keyboard;
  :func:`pick_scene` — choose a scene in the page's dropdown.
* :func:`image_stats` — is a render blank; how much two renders differ.
* :func:`raw_client` / :func:`send_value` / :func:`still_connected` — a websocket client speaking viser's
  protocol without a browser (what a page's script, or a hostile one, can send); :func:`send_upload`,
  :func:`start_upload` and :func:`send_part` upload a file through it, truthfully or not.
* :func:`open_scene` / :func:`matrix` / :func:`project` — headless: switch to a scene and play one frame; a
  handle's attitude as a rotation matrix; where a camera draws points.

Fixtures built on them live in ``tests/conftest.py`` (``browser``) — module-scoped so one Chromium
serves a whole test module.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import socket
import struct
import time
from collections.abc import Callable, Iterator
from typing import Any

import msgspec
import numpy as np
import pytest
import viser
import zstandard
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from app.server import App
from app.serving.simulation import Simulation

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
VIEWPORT = {"width": 960, "height": 720}  # small: SwiftShader renders on the CPU
CAMERA_MESSAGE = msgspec.msgpack.encode(
    {
        "type": "ViewerCameraMessage",
        "wxyz": (1.0, 0.0, 0.0, 0.0),
        "position": (3.0, -3.0, 2.0),
        "fov": 0.9,
        "near": 0.01,
        "far": 100.0,
        "image_height": 480,
        "image_width": 640,
        "look_at": (0.0, 0.0, 0.0),
        "up_direction": (0.0, 0.0, 1.0),
    }
)
"""The camera a page reports as soon as it connects: viser counts a client only once it has (raw clients)."""


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def running_app(
    scene: str | None = None,
    *,
    start_loop: bool = True,
    private: bool = False,
    presenter: bool = False,
    pin: str | None = None,
    state: str | None = None,
    dark: bool = False,
    projector: bool = False,
    share: bool = False,
    lecture: str | None = None,
    answers: str | None = None,
    caps: Any = None,
    lang: str = "en",
) -> Iterator[Any]:
    """An App on a free port (``private``: one simulation per browser; ``presenter``: presenter mode on
    127.0.0.1; ``state``: a state text to start from; ``dark``: the dark look; ``projector``: projector
    mode; ``share``: viser's share button shown; ``lecture``: a lecture file or name to follow; ``answers``: the class questions' CSV;
    ``caps``: an ``app.guards.admission.Caps``; ``lang``: the language of a browser that prefers none we speak);
    stopped on exit."""
    from app.server import App

    app = App(
        host="127.0.0.1",
        port=free_port(),
        scene=scene,
        start_loop=start_loop,
        private=private,
        presenter=presenter,
        pin=pin,
        state=state,
        dark=dark,
        projector=projector,
        share=share,
        lecture=lecture,
        answers=answers,
        caps=caps,
        lang=lang,
    )
    try:
        yield app
    finally:
        app.stop()


def chromium_or_skip() -> str:
    """Path of Debian's Chromium; skip (or, under RBL_REQUIRE_BROWSER=1, fail) when it is missing."""
    if os.path.exists(CHROMIUM):
        return CHROMIUM
    found = shutil.which("chromium")  # Debian's package on another PATH entry
    if found:
        return found
    message = f"{CHROMIUM} not found: the browser tests need Debian's chromium (apt-get install chromium)"
    if os.environ.get("RBL_REQUIRE_BROWSER") == "1":
        pytest.fail(message + " and RBL_REQUIRE_BROWSER=1 requires them")
    pytest.skip(message)


DEVICES: dict[str, dict[str, Any]] = {}
"""Playwright's device descriptors (``playwright.devices``: viewport, device pixel ratio, touch, mobile, user
agent), by name (``"iPhone 13"``), as options of ``new_context`` in Chromium; filled when Chromium starts."""


def _for_chromium(descriptor: dict[str, Any]) -> dict[str, Any]:
    """A device descriptor as Chromium's context options (the browser it names by default is not an option)."""
    return {k: v for k, v in descriptor.items() if k != "default_browser_type"}


@contextlib.contextmanager
def launch_chromium() -> Iterator[Any]:
    """A headless Chromium (Playwright sync API, Debian's binary; never ``playwright install``)."""
    path = chromium_or_skip()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        DEVICES.update({name: _for_chromium(d) for name, d in pw.devices.items()})
        browser = pw.chromium.launch(executable_path=path, args=CHROMIUM_ARGS, headless=True)
        try:
            yield browser
        finally:
            browser.close()


FRAME_RATE = 5
"""Frames per second a test page draws at most. Headless Chromium draws WebGL on the CPU (SwiftShader):
about 60 ms of CPU a frame at 960×720, so a page showing a moving body, which viser's client redraws as
fast as it can, kept one and a half of the machine's two cores busy for as long as it was open, and the
pages of two test workers starved each other and the servers they test. The page's own behaviour (its
controls, its messages, what it draws) is the same at any rate; a test that needs the page to have drawn
waits for ``window.rblFrames`` to count on. On two idle cores the suite took 400 s at 10 frames/s and
335-345 s at 5."""

PACE_FRAMES = (
    """(() => {
  // Every requestAnimationFrame callback of the page runs in one batch at most FRAME_RATE times a second;
  // window.rblFrames counts the batches, so a test can wait for the page to have drawn.
  const native = window.requestAnimationFrame.bind(window);
  const period = 1000 / FRAME_RATE;
  let queue = new Map(), next = 1, scheduled = false, last = -Infinity;
  window.rblFrames = 0;
  function run(time) {
    if (time - last < period - 2) { native(run); return; }
    last = time; scheduled = false; window.rblFrames += 1;
    const batch = queue; queue = new Map();
    for (const callback of batch.values()) {
      try { callback(time); } catch (error) { setTimeout(() => { throw error; }); }
    }
  }
  window.requestAnimationFrame = (callback) => {
    const id = next++;
    queue.set(id, callback);
    if (!scheduled) { scheduled = true; native(run); }
    return id;
  };
  window.cancelAnimationFrame = (id) => { queue.delete(id); };
})();"""
).replace("FRAME_RATE", str(FRAME_RATE))


def paced_context(browser: Any, **options: Any) -> Any:
    """A new context of ``browser`` (a Playwright ``Browser``) whose pages draw at most
    :data:`FRAME_RATE` frames per second (:data:`PACE_FRAMES`)."""
    context = browser.new_context(**options)
    context.add_init_script(PACE_FRAMES)
    return context


class ModuleBrowser:
    """A Playwright ``Browser`` shared by many test modules, seen by one: what it opens through
    ``new_page`` and ``new_context`` is closed by :meth:`close_opened`; everything else is the browser's.
    Its pages draw at most :data:`FRAME_RATE` frames per second."""

    def __init__(self, browser: Any) -> None:
        self._browser = browser
        self._opened: list[Any] = []

    def new_page(self, **options: Any) -> Any:
        return self.new_context(**options).new_page()

    def new_context(self, **options: Any) -> Any:
        context = paced_context(self._browser, **options)
        self._opened.append(context)
        return context

    def close_opened(self) -> None:
        """Close every context (and its pages) opened through this object."""
        for context in self._opened:
            with contextlib.suppress(Exception):  # already closed by the test
                context.close()
        self._opened.clear()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._browser, name)


def wait_for(
    condition: Callable[[], Any], timeout: float = 20.0, interval: float = 0.05, what: str = "condition"
) -> Any:
    """Poll ``condition`` until it returns something truthy; fail after ``timeout`` seconds. The first polls
    come quickly (2 ms apart, doubling up to ``interval`` s): most conditions hold within milliseconds."""
    deadline = time.monotonic() + timeout
    pause = min(0.002, interval)
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(pause)
        pause = min(2 * pause, interval)


def open_page(browser: Any, app: Any, timeout: float = 90.0, viewport: dict | None = None) -> tuple[Any, Any]:
    """Open the app in a new page; returns (page, client) once connected and the canvas exists.

    A page with a moving body drawn in software (SwiftShader) takes all the CPU it can get, about one and a
    half cores of two whatever its frame rate or size: a second page, loading beside it while the other
    test worker runs, has taken more than 30 s to show its canvas in CI. Hence the long ``timeout`` (s)."""
    before = set(app.server.get_clients())
    page = browser.new_page(viewport=viewport or VIEWPORT)
    page.goto(app.url, wait_until="domcontentloaded")
    client_id = wait_for(lambda: set(app.server.get_clients()) - before, timeout, what="the page to connect")
    page.wait_for_selector("canvas", timeout=timeout * 1000)
    client = app.server.get_clients()[next(iter(client_id))]
    return page, client


QUIET = """([ms, cap]) => new Promise((resolve) => {
  const done = (still) => { observer.disconnect(); clearTimeout(limit); resolve(still); };
  let timer = setTimeout(() => done(true), ms);
  const limit = setTimeout(() => done(false), cap);
  const observer = new MutationObserver(() => { clearTimeout(timer); timer = setTimeout(() => done(true), ms); });
  observer.observe(document.body, {subtree: true, childList: true, attributes: true, characterData: true});
})"""


def quiet(page: Any, still: float = 0.15, cap: float = 5.0) -> bool:
    """Wait until the page's DOM has not changed for ``still`` seconds (at most ``cap`` seconds); True if it
    went still. A page whose panel has stopped re-rendering reads one layout."""
    return bool(page.evaluate(QUIET, [still * 1000, cap * 1000]))


def control_id(page: Any, label: str, timeout: float = 30.0) -> str:
    """The DOM id of the viser control whose label text is ``label`` (viser labels it with for=id).

    Waits for the control to appear: after a scene switch the server has the new controls before the
    page has drawn them, more so on a loaded machine.
    """
    try:
        page.wait_for_function(
            """(text) => [...document.querySelectorAll('label[for]')].some(el => el.textContent.trim() === text)""",
            arg=label,
            timeout=timeout * 1000,
        )
    except Exception:  # noqa: BLE001 - reported below with the label that never came
        pass
    found = page.evaluate(
        """(text) => { for (const el of document.querySelectorAll('label[for]')) {
               if (el.textContent.trim() === text) return el.getAttribute('for'); } return null; }""",
        label,
    )
    if not found:
        raise AssertionError(f"no control labelled {label!r} in the page")
    return found


def click(locator: Any, timeout: float = 30.0) -> None:
    """Click an element that is in the page, without waiting for it to be "stable".

    The panel re-renders every frame while the clock runs, so Playwright's actionability wait for a
    stable bounding box can time out on a loaded machine; we wait only for the element to be attached
    and visible, then click it where it is.
    """
    locator.first.wait_for(state="visible", timeout=timeout * 1000)
    _wait_until_still(locator.first)
    locator.first.click(force=True, timeout=timeout * 1000)


def _wait_until_still(element: Any, timeout: float = 5.0, interval: float = 0.1) -> None:
    """Wait until ``element`` is in the same place in two reads ``interval`` apart (at most ``timeout``).

    A row that comes or goes above a button (a hidden "Use its convex hull instead", a readout's first
    value) moves the button while the page lays out the update; a forced click where the button was
    lands on its neighbour. Past ``timeout`` the click goes ahead where the element is.
    """
    deadline = time.monotonic() + timeout
    box = element.bounding_box()
    while time.monotonic() < deadline:
        time.sleep(interval)
        now = element.bounding_box()
        if now is not None and now == box:
            return
        box = now


def click_until(locator: Any, condition: Callable[[], Any], what: str, attempts: int = 3, each: float = 10.0) -> Any:
    """Click ``locator`` until ``condition`` holds, as a user clicks again when nothing happened.

    For buttons whose effect is checked on the server (a scene hand-over): a click lost to a panel
    that re-laid itself out is retried, at most ``attempts`` times, ``each`` seconds apart.
    """
    for attempt in range(1, attempts + 1):
        click(locator)
        try:
            return wait_for(condition, timeout=each, what=f"{what} (click {attempt} of {attempts})")
        except AssertionError:
            if attempt == attempts:
                raise
    raise ValueError(f"attempts must be at least 1, got {attempts}")


def pick_scene(page: Any, title: str, attempts: int = 3) -> None:
    """Choose a scene in the page's Scene dropdown, as a user does.

    A panel that re-renders just as the dropdown opens (a frame's readouts, a loaded machine) can close
    it again: the dropdown is reopened, up to ``attempts`` times, as a user would.
    """
    option = page.get_by_role("option", name=title, exact=True).first
    for attempt in range(attempts):
        click(page.locator(f"[id='{control_id(page, 'Scene')}']"))
        try:
            option.wait_for(state="visible", timeout=10_000)
        except Exception:  # noqa: BLE001 - the list closed again: reopen it
            if attempt == attempts - 1:
                raise
            page.keyboard.press("Escape")
            continue
        option.click(force=True, timeout=30_000)
        return


def slider_by_label(page: Any, label: str) -> Any:
    """The slider thumb (role=slider) of the viser slider whose label text is ``label``."""
    return page.locator(f"[id='{control_id(page, label)}'] [role=slider]")


def slider_disabled(page: Any, label: str) -> bool | None:
    """Whether the slider labelled ``label`` is disabled (``aria-disabled``); None while there is none.

    One read in the page: a slider that is replaced between finding its id and reading it (a copy
    giving way to the lecture) cannot leave the caller waiting on a node that is gone.
    """
    state = page.evaluate(
        """(text) => { for (const el of document.querySelectorAll('label[for]')) {
               if (el.textContent.trim() !== text) continue;
               const box = document.getElementById(el.getAttribute('for'));
               const thumb = box && box.querySelector('[role=slider]');
               if (thumb) return thumb.getAttribute('aria-disabled') === 'true'; }
             return null; }""",
        label,
    )
    return None if state is None else bool(state)


SLIDER_THUMB = """([id, focus]) => {
  const thumb = document.querySelector(`[id='${id}'] [role=slider]`);
  if (!thumb) return null;
  if (focus) { thumb.scrollIntoView({block: 'center'}); thumb.focus(); }
  return thumb.getAttribute('aria-valuenow');
}"""
"""A slider's thumb read (its ``aria-valuenow``), and focused if asked, in one evaluation in the page: a page
drawing a moving body in software can take a second a frame on a loaded machine, and a Playwright locator's
several round trips to it (resolve, check, act) took longer than 30 s in CI."""


def slider_value(page: Any, label: str) -> str | None:
    """The value (``aria-valuenow``) the slider labelled ``label`` shows; None while it has no thumb."""
    return page.evaluate(SLIDER_THUMB, [control_id(page, label), False])


def nudge_slider(page: Any, label: str, key: str = "ArrowRight", times: int = 1) -> None:
    """Focus a slider in the page and press a key (one step per press), like a user with a keyboard."""
    # Focus through the DOM and type on the keyboard: no wait for a re-rendering thumb to be "stable".
    wait_for(
        lambda: page.evaluate(SLIDER_THUMB, [control_id(page, label), True]) is not None,
        30,
        what=f"the slider {label!r}",
    )
    for _ in range(times):
        page.keyboard.press(key)


def image_stats(image: np.ndarray) -> float:
    """Standard deviation of the pixel values: about 0 for a blank (single-colour) image."""
    return float(np.asarray(image, dtype=float)[..., :3].std())


def image_difference(a: np.ndarray, b: np.ndarray) -> float:
    """Mean absolute difference of two renders (0-255 scale)."""
    return float(np.abs(np.asarray(a, dtype=float)[..., :3] - np.asarray(b, dtype=float)[..., :3]).mean())


FRAME = 1.0 / 60.0
"""One frame of the real-time loop at 60 frames per second, s."""


def open_scene(app: Any, name: str) -> Any:
    """Switch a headless app to ``name``, play at 1x and advance one frame; returns the scene."""
    app.switch_scene(name)
    app.set_speed(1.0)
    app.set_playing(True)
    app.frame(FRAME)
    return app.scene


def project(points: Any, eye: Any, target: Any, width: float, height: float, fov: float) -> np.ndarray:
    """Pixels (n, 2), x right and y down, where a perspective camera at ``eye`` looking at ``target`` (up +z,
    vertical field ``fov`` rad, a ``width`` × ``height`` px view) draws ``points`` (n, 3), m."""
    eye, target = np.asarray(eye, dtype=float), np.asarray(target, dtype=float)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = np.asarray(points, dtype=float).reshape(-1, 3) - eye
    scale = 0.5 * height / (np.tan(0.5 * fov) * (d @ forward))
    return np.column_stack([0.5 * width + scale * (d @ right), 0.5 * height - scale * (d @ up)])


def matrix(handle: Any) -> np.ndarray:
    """The rotation matrix (3, 3) of a viser handle's ``wxyz`` quaternion."""
    from scipy.spatial.transform import Rotation

    w, x, y, z = handle.wxyz
    return Rotation.from_quat([x, y, z, w]).as_matrix()


# --------------------------------------------------------------------------------------------------
# Raw websocket clients: what a page's script (or a hostile one) can send, without a browser.
# --------------------------------------------------------------------------------------------------
@contextlib.contextmanager
def raw_client(app: Any, wait: bool = True, source: str | None = None, headers: dict | None = None) -> Iterator[Any]:
    """A websocket client speaking viser's protocol, as the page's script does (``wait``: until the
    server has registered it; ``app`` then needs ``.server``, otherwise only ``.port``; ``source``: the
    loopback address it connects from, 127.0.0.2 standing in for another machine; ``headers``: more
    headers for the request that opens it, a cookie say)."""
    before = set(app.server.get_clients()) if wait else set()
    more: dict[str, Any] = {} if source is None else {"source_address": (source, 0)}
    ws = connect(
        f"ws://127.0.0.1:{app.port}",
        additional_headers=headers,
        **more,
        subprotocols=[f"viser-v{viser.__version__}"],
        max_size=None,
        max_queue=None,  # frames the test does not read are buffered, so closing does not wait behind them
        open_timeout=30,
        close_timeout=1,  # unread frames delay the server's close frame; a browser closing does not wait
    )
    try:
        # viser counts a client as connected once it reports its camera, as the page does at once.
        ws.send(CAMERA_MESSAGE)
        if wait:
            wait_for(lambda: set(app.server.get_clients()) - before, what="the client to be registered")
        yield ws
    finally:
        ws.close()


def drain(ws: Any) -> int:
    """Read whatever the server has sent so far, as a page does continuously; returns how many messages."""
    count = 0
    while True:
        try:
            ws.recv(timeout=0)
        except TimeoutError:
            return count
        count += 1


def received(ws: Any, seconds: float = 0.0) -> list[dict[str, Any]]:
    """Decode what the server sends this client for ``seconds`` (at least what is already there): viser's
    wire format is two lengths, zstd-compressed msgpack of ``{"messages": [...]}``, then raw buffers."""
    out: list[dict[str, Any]] = []
    deadline = time.monotonic() + seconds
    for _ in range(100_000):  # a running simulation never stops sending: the deadline ends the read
        try:
            raw = ws.recv(timeout=max(0.0, deadline - time.monotonic()))
        except TimeoutError:
            return out
        inner_size = int.from_bytes(raw[:8], "little")
        compressed = int.from_bytes(raw[8:16], "little")
        inner = zstandard.ZstdDecompressor().decompress(raw[16 : 16 + compressed], max_output_size=inner_size)
        out.extend(msgspec.msgpack.decode(inner)["messages"])
        if time.monotonic() > deadline:
            return out
    return out


def click_button(ws: Any, uuid: str) -> None:
    """Press a button as the page does (a value update of True)."""
    send_value(ws, uuid, True)


def send_value(ws: Any, uuid: str, value: Any) -> None:
    ws.send(msgspec.msgpack.encode({"type": "GuiUpdateMessage", "uuid": uuid, "updates": {"value": value}}))


UPLOAD_PART = 512 * 1024
"""Bytes in one part of an upload, as viser's page sends them."""


def start_upload(ws: Any, button: str, filename: str, size: int, parts: int, transfer: str | None = None) -> str:
    """Announce an upload to the button ``button`` as the page does (``size`` and ``parts`` as declared,
    true or not); returns the transfer's uuid."""
    import uuid

    transfer = transfer or uuid.uuid4().hex
    ws.send(
        msgspec.msgpack.encode(
            {
                "type": "FileTransferStartUpload",
                "source_component_uuid": button,
                "transfer_uuid": transfer,
                "filename": filename,
                "mime_type": "",
                "part_count": parts,
                "size_bytes": size,
            }
        )
    )
    return transfer


def send_part(ws: Any, button: str, transfer: str, index: int, content: bytes) -> None:
    """One part of an upload, as the page sends it."""
    message = {
        "type": "FileTransferPart",
        "source_component_uuid": button,
        "transfer_uuid": transfer,
        "part_index": index,
        "content": content,
    }
    ws.send(msgspec.msgpack.encode(message))


def send_upload(ws: Any, button: str, filename: str, content: bytes, declared: int | None = None) -> str:
    """Upload a file to the button ``button`` as the page does (start, then parts of :data:`UPLOAD_PART`);
    ``declared`` is the size announced (default: the true one). Returns the transfer's uuid."""
    chunks = [content[i : i + UPLOAD_PART] for i in range(0, len(content), UPLOAD_PART)]
    transfer = start_upload(ws, button, filename, len(content) if declared is None else declared, len(chunks))
    for index, chunk in enumerate(chunks):
        send_part(ws, button, transfer, index, chunk)
    return transfer


def still_connected(ws: Any, seconds: float = 10.0, app: App | Simulation | None = None) -> bool:
    """The server still talks to this client: a message arrives within ``seconds`` and the connection is
    open. With ``app``, the client first sends a value to the read-only time display, which the server
    always answers (it sets that client's display back), so a paused clock cannot make a live client look
    dead. ``app`` is the app (its shared simulation) or the simulation this client sees."""
    if app is not None:
        simulation = app.simulation if isinstance(app, App) else app
        drain(ws)
        send_value(ws, simulation.time_text._impl.uuid, "still there?")
    deadline = time.monotonic() + seconds
    try:
        while time.monotonic() < deadline:
            try:
                ws.recv(timeout=0.2)
                return True
            except TimeoutError:
                continue
    except ConnectionClosed:
        return False
    return False


def glb_with_nodes(n_nodes: int, mesh: Any = None) -> bytes:
    """A valid GLB of one mesh (a box) shown by ``n_nodes`` nodes (instancing: small file, huge scene)."""
    import trimesh

    box = (mesh or trimesh.creation.box(extents=(0.3, 0.2, 0.1))).export(file_type="glb")
    json_length, _ = struct.unpack_from("<II", box, 12)
    document = json.loads(box[20 : 20 + json_length])
    binary = box[20 + json_length :]
    document["nodes"] = [{"mesh": 0, "translation": [float(i), 0.0, 0.0]} for i in range(n_nodes)]
    document["scenes"] = [{"nodes": list(range(n_nodes))}]
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body
