"""The teacher's view of private sessions: a table of what every student's session shows, and Spotlight.

In a pool of processes (``rigid-body-lab rooms``), the table is the whole pool's, shared through Redis
(:mod:`app.teaching.pool_table`), and Spotlight reaches a session on any of its processes.

More in docs/app-notes.md (``app.teaching.teacher``).
"""

from __future__ import annotations

import copy
import math
import threading
import time
import traceback
import unicodedata
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import viser

from app.contracts import ClientId
from app.guards.callbacks import shielded_handler
from app.guards.handles import is_removed
from app.guards.wire import departed
from app.language.words import escaped, joined, mark, say
from app.teaching.pin_gate import PinGate
from app.teaching.pool_table import PoolPlace, PoolRow, PoolTable, SessionFields, place_from_environment
from app.teaching.teacher_panel import TeacherPanel

if TYPE_CHECKING:  # annotations only: the app and its simulations are above teaching/
    from app.serving.app import App
    from app.serving.simulation import Simulation

__all__ = [
    "MAIN_PARAMETERS",
    "MAX_NAME",
    "MAX_TABLE",
    "REFRESH",
    "Row",
    "TeacherDesk",
    "clean_name",
    "parameters",
    "table_html",
]

MAX_NAME = 40
"""Longest name a student may give, characters (after cleaning)."""

MAIN_PARAMETERS = 3
"""How many of a scene's controls the table shows: its first ones, which are its main parameters."""

REFRESH = 1.0
"""Seconds between two rewrites of the table (sooner when the pool's other processes' rows change)."""

MAX_TABLE = 1000
"""Rows the table shows at most (a pool's processes together)."""

SKIPPED = frozenset({"Preset"})
"""Controls that are not parameters (a preset's name says nothing once a slider has moved)."""

WHERE = mark("The teacher PIN is the one given with --pin where the server was started.")


def clean_name(text: Any) -> str:
    """A name fit for the table: letters, digits, spaces and ``.-'_`` only, at most :data:`MAX_NAME` long.

    Anything else (markup, control and direction-override characters, combining marks piled up) becomes a
    space; runs of spaces become one. Not text gives "". The table escapes it again when it writes HTML.
    """
    if not isinstance(text, str):
        return ""
    kept = "".join(ch if ch.isalnum() or ch in " .-'_" else " " for ch in unicodedata.normalize("NFKC", text))
    return " ".join(kept.split())[:MAX_NAME].strip()


def _value_text(value: Any) -> str:
    if isinstance(value, bool):
        return mark("on") if value else mark("off")
    if isinstance(value, float):
        return say("{value:.3g}", value=value) if math.isfinite(value) else str(value)
    if isinstance(value, (tuple, list)):
        return joined([_value_text(v) for v in value], ", ")
    text = str(value)
    return text if len(text) <= 32 else text[:31] + "…"


def parameters(session: Simulation, count: int = MAIN_PARAMETERS) -> tuple[tuple[str, str], ...]:
    """The first ``count`` parameters of a session's scene as (label, value text); () without a scene."""
    out: list[tuple[str, str]] = []
    for handle in list(getattr(session, "scene_inputs", ())):
        label = str(handle.label)
        if label in SKIPPED or is_removed(handle):
            continue
        out.append((label, _value_text(handle.value)))
        if len(out) == count:
            break
    return tuple(out)


@dataclass(frozen=True)
class Row(SessionFields):
    """One session in the teacher's table.

    Attributes
    ----------
    number : int
        The session's number (anonymous; given in the order the browsers connected, never reused).
    name : str
        The name its student typed (cleaned), or "".
    scene : str
        The title of its scene ("—" while none is built).
    parameters : tuple of (str, str)
        Its scene's main parameters, (label, value text).
    time : float
        Its simulated time, s.
    playing : bool
        Whether its clock runs.
    idle : float
        Seconds since its student last did something (a control, the scene, the clock, the camera).
    """

    idle: float


def _idle_text(seconds: float) -> str:
    if seconds < 2.0:
        return mark("now")
    if seconds < 120.0:
        return say("{seconds:.0f} s ago", seconds=seconds)
    return say("{minutes:.0f} min ago", minutes=seconds / 60.0)


_HEADINGS = (mark("Session"), mark("Scene"), mark("Main parameters"), mark("Time"), mark("Last activity"))
_HEAD = '<th scope="col">{heading}</th>'
_ROW = '<tr><th scope="row">{who}</th><td>{scene}</td><td>{params}</td><td>{clock}</td><td>{idle}</td></tr>'
_TABLE = (
    '<table class="rbl-teacher" style="width:100%;font-size:0.8em;border-collapse:collapse;text-align:left">'
    '<caption style="text-align:left">{caption}</caption><thead><tr>{head}</tr></thead>'
    "<tbody>{body}</tbody></table>"
)


def table_html(rows: Sequence[Row], notice: str = "") -> str:
    """The teacher's table as HTML (viser's Html element); every text from a session is escaped.

    ``notice``: a line shown above the table (plain text, escaped), e.g. that the pool's other processes
    cannot be reached."""
    # Markup templates (not for the translators), filled with words that are: each translated on the wire.
    e = escaped
    head = joined([say(_HEAD, heading=h) for h in _HEADINGS])
    body = []
    for row in rows:
        who = say("{number} · {name}", number=row.number, name=e(row.name)) if row.name else str(row.number)
        pairs = [say("{label} = {value}", label=e(label), value=e(value)) for label, value in row.parameters]
        params = joined(pairs, "<br>") or "—"
        clock = say("{time:.1f} s", time=row.time) if row.playing else say("{time:.1f} s (paused)", time=row.time)
        body.append(say(_ROW, who=who, scene=e(row.scene), params=params, clock=e(clock), idle=e(_idle_text(row.idle))))
    count = len(rows)
    if count == 0:
        caption = mark("No student is connected yet")
    else:
        caption = (
            say("{count} session connected", count=count)
            if count == 1
            else say("{count} sessions connected", count=count)
        )
    if notice:
        caption = say("{notice}<br>{caption}", notice=e(notice), caption=caption)
    return say(_TABLE, caption=caption, head=head, body=joined(body))


REFUSED = mark("Refused")


def _spotlit(number: int, name: str, title: str, t: float) -> str:
    """What the teacher is told when a session is copied into their view."""
    who = say("Session {number} ({name})", number=number, name=name) if name else say("Session {number}", number=number)
    return say("{who}: {title} at t = {t:.2f} s, now in your view.", who=who, title=title, t=t)


@dataclass
class _Seat:
    """What the desk keeps of one connected browser."""

    number: int
    client: viser.ClientHandle
    panel: TeacherPanel
    name: str = ""
    signature: tuple[Any, ...] = ()
    clock: float = 0.0  # simulated time at the last look, s
    active_at: float = field(default_factory=time.time)  # wall clock, s


class TeacherDesk:
    """The teacher's view of an :class:`app.serving.app.App` in private mode (``--private --pin PIN``).

    Every private session gets a number, a "Your name" box and the teacher PIN box
    (:class:`app.teaching.teacher_panel.TeacherPanel`). A browser with the PIN sees the table of the other
    sessions (:func:`table_html`), rewritten every :data:`REFRESH` seconds by a thread of its own, and can
    spotlight one: copy its state into its own session (:meth:`spotlight`).

    Parameters
    ----------
    app : app.serving.app.App
        The app: its ``sessions`` (client id -> Simulation, :class:`app.contracts.Sessions`) and ``server``.
    pin : str
        The teacher PIN (4 to 32 letters or digits); guessing is limited as the presenter's is.
    place : PoolPlace or None or "environment"
        This process's place in a pool sharing its table through Redis (:mod:`app.teaching.pool_table`);
        None: a process of its own; default: as its environment says (:func:`place_from_environment`).
        Process I of N numbers its sessions I, I + N, I + 2N, ...: a number names one session of the pool.
    """

    def __init__(self, app: App, pin: str, place: PoolPlace | Literal["environment"] | None = "environment") -> None:
        self.app = app
        self.gate = PinGate(pin, WHERE, identify=app.who)
        self.teachers: set[Any] = set()
        self._seats: dict[Any, _Seat] = {}
        self.place = place_from_environment() if place == "environment" else place
        self._next = 1 if self.place is None else self.place.index
        self._step = 1 if self.place is None else self.place.size
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._wake = threading.Event()  # the pool's other rows changed: rewrite the tables now
        self._thread: threading.Thread | None = None
        self.pool: PoolTable | None = None
        if self.place is not None:
            self.pool = PoolTable(self.place, self._pool_rows, self.answer, lambda: bool(self.teachers), self._wake.set)
        app.server.on_client_disconnect(self.left)

    # ------------------------------------------------------------------ browsers come and go
    def joined(self, client: viser.ClientHandle, session: Simulation) -> int:
        """A browser's private session is ready: number it and give it its controls; returns its number."""
        with self._lock:
            number = self._next
            self._next += self._step
        panel = TeacherPanel(client, number)
        seat = _Seat(number, client, panel)
        with self._lock:
            self._seats[client.client_id] = seat
        panel.name.on_update(lambda _: self._rename(seat))
        panel.open.on_click(self._safely(lambda event: self.open_view(event.client, panel.pin.value)))
        if departed(client):  # it left while its controls were made: its disconnect may have come first
            self.left(client)
        return number

    def left(self, client: viser.ClientHandle) -> None:
        """A browser left: its number goes for good."""
        with self._lock:
            self._seats.pop(client.client_id, None)
            self.teachers.discard(client.client_id)
        self.gate.forget(client.client_id)

    def _rename(self, seat: _Seat) -> None:
        name = clean_name(seat.panel.name.value)
        if name != seat.name:
            seat.name = name
            seat.active_at = time.time()

    def number_of(self, client_id: ClientId) -> int | None:
        """The session number of a connected browser, or None."""
        with self._lock:
            seat = self._seats.get(client_id)
        return None if seat is None else seat.number

    def name_of(self, client_id: ClientId) -> str | None:
        """The name a connected browser gave (cleaned; "" if none), or None."""
        with self._lock:
            seat = self._seats.get(client_id)
        return None if seat is None else seat.name

    def panel_of(self, client_id: ClientId) -> TeacherPanel | None:
        """A connected browser's controls for the teacher's view, or None."""
        with self._lock:
            seat = self._seats.get(client_id)
        return None if seat is None else seat.panel

    # ------------------------------------------------------------------ the table
    def rows(self, now: float | None = None) -> list[Row]:
        """The students' sessions (not the teachers'), by number; notes what changed since the last look.

        ``now`` is the wall clock (s, :func:`time.time`), for tests.
        """
        now = time.time() if now is None else now
        with self._lock:
            seats = [(cid, seat) for cid, seat in self._seats.items() if cid not in self.teachers]
        sessions = {cid: self.app.sessions.get(cid) for cid, _ in seats}
        out = []
        for cid, seat in sorted(seats, key=lambda item: item[1].number):
            session = sessions[cid]
            if session is None:
                continue
            scene = session.scene
            main = parameters(session)
            t, playing = float(session.time), bool(session.playing)
            signature = (scene.name if scene is not None else None, main, playing, float(session.speed))
            # A change of scene, control or clock, a step or a reset while paused, or a camera moved.
            if signature != seat.signature or (t < seat.clock) or (not playing and t != seat.clock):
                if seat.signature:
                    seat.active_at = now
                seat.signature = signature
            seat.clock = t
            try:
                seat.active_at = max(seat.active_at, float(seat.client.camera.update_timestamp))
            except AssertionError:  # no camera reported yet
                pass
            out.append(
                Row(
                    number=seat.number,
                    name=seat.name,
                    scene=scene.title if scene is not None else "—",
                    parameters=main,
                    time=t,
                    playing=playing,
                    idle=max(0.0, now - seat.active_at),
                )
            )
        return out

    def refresh(self, now: float | None = None) -> list[Row]:
        """Look at every session and rewrite every teacher's table (one Html update per teacher, only if it
        changed) and their dropdowns (only when a session came or went). Returns the rows (the whole pool's)."""
        rows = self.table_rows(now)
        with self._lock:
            panels = [self._seats[cid].panel for cid in self.teachers if cid in self._seats]
        if panels:
            table, numbers = table_html(rows, self.notice()), [str(row.number) for row in rows]
            for panel in panels:
                try:
                    panel.show_numbers(numbers)
                    panel.show_table(table)
                except Exception:  # noqa: BLE001 - a teacher that just left must not stop the others' tables
                    traceback.print_exc()
        return rows

    def table_rows(self, now: float | None = None) -> list[Row]:
        """This process's rows (:meth:`rows`) and, in a pool, the other processes' as last read, by number
        (at most :data:`MAX_TABLE`)."""
        now = time.time() if now is None else now
        rows = self.rows(now)
        if self.pool is not None:
            rows += [
                Row(r.number, r.name, r.scene, r.parameters, r.time, r.playing, max(0.0, now - r.active_at))
                for r in self.pool.remote_rows()
            ]
            rows.sort(key=lambda row: row.number)
        return rows[:MAX_TABLE]

    def notice(self) -> str:
        """What the table says above itself: in a pool whose Redis cannot be reached, that it shows this
        process's sessions only; otherwise ""."""
        if self.pool is None or self.pool.available:
            return ""
        return say(
            "The pool's shared table (Redis at {address}) cannot be reached: only this process's sessions are "
            "shown; trying again.",
            address=self.pool.address,
        )

    def _pool_rows(self) -> list[PoolRow]:
        """This process's rows as the pool shares them (on the pool's thread)."""
        now = time.time()
        return [
            PoolRow(r.number, r.name, r.scene, r.parameters, r.time, r.playing, round(now - r.idle, 1))
            for r in self.rows(now)
        ]

    def start(self) -> None:
        """Rewrite the tables every :data:`REFRESH` seconds on a thread of their own (daemon), and share
        them with the pool (its own thread)."""
        if self._thread is not None:
            return
        self._stop.clear()
        self._thread = threading.Thread(target=self._run, name="rbl-teacher", daemon=True)
        self._thread.start()
        if self.pool is not None:
            self.pool.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            self._wake.wait(REFRESH)
            self._wake.clear()
            if self._stop.is_set():
                break
            try:
                self.refresh()
            except Exception:  # noqa: BLE001 - the table goes on
                traceback.print_exc()

    def stop(self) -> None:
        """Stop the thread that rewrites the tables (and the pool's, taking this process's rows out)."""
        self._stop.set()
        self._wake.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
            self._thread = None
        if self.pool is not None:
            self.pool.stop()

    # ------------------------------------------------------------------ the two actions
    def open_view(self, client: viser.ClientHandle, typed: Any) -> bool:
        """Open the teacher's view for ``client`` if ``typed`` is the PIN; returns whether it has it now."""
        cid = client.client_id
        with self._lock:
            seat = self._seats.get(cid)
            if seat is None:
                return False
            if cid in self.teachers:
                return True
        refusal = self.gate.refusal(cid, typed)
        if refusal is not None:
            title, body = refusal
            self._tell(client, title, body, error=title != "Wrong PIN")
            return False
        with self._lock:
            self.teachers.add(cid)
        rows = self.table_rows()
        spotlight = seat.panel.show_view(table_html(rows, self.notice()), [str(row.number) for row in rows])
        spotlight.on_click(self._safely(lambda event: self.spotlight(event.client, seat.panel.choice.value)))
        self._tell(
            client,
            mark("Teacher's view"),
            mark(
                "The table lists every student's session, rewritten every second; Spotlight copies the one chosen "
                "into your own view (theirs goes on untouched)."
            ),
        )
        return True

    def spotlight(self, client: viser.ClientHandle, choice: Any) -> bool:
        """Copy the session numbered ``choice`` (its text, as in the dropdown) into ``client``'s own session:
        scene, parameters, motion, time, clock and the student's camera. The student's session is only read.
        Returns whether it was copied; a refusal is told to ``client`` only."""
        cid = client.client_id
        if cid not in self.teachers:
            self._tell(client, REFUSED, mark("Only the teacher's view can spotlight a session."), error=True)
            return False
        if not isinstance(choice, str) or not choice.isdigit() or len(choice) > 9:
            self._tell(
                client,
                REFUSED,
                say("Choose a session by its number, not {choice}.", choice=repr(str(choice)[:20])),
                error=True,
            )
            return False
        number = int(choice)
        with self._lock:
            found = next(((k, s) for k, s in self._seats.items() if s.number == number), None)
            teaching = found is not None and found[0] in self.teachers
        if found is None and self.pool is not None and self.pool.place.owner(number) != self.pool.place.index:
            return self._spotlight_remote(client, number, self.pool)
        if teaching:
            self._tell(
                client,
                REFUSED,
                say("Session {number} is a teacher's view, not a student's.", number=number),
                error=True,
            )
            return False
        seat = found[1] if found is not None else None
        student = self.app.sessions.get(seat.client.client_id) if seat is not None else None
        own = self.app.sessions.get(cid)
        if seat is None or student is None:
            self._tell(
                client,
                REFUSED,
                say("Session {number} is not connected (it may just have left).", number=number),
                error=True,
            )
            return False
        if own is None:
            self._tell(client, REFUSED, mark("Your own session is not ready yet: try again in a moment."), error=True)
            return False
        try:
            state = student.snapshot()
        except ValueError as exc:
            self._tell(
                client,
                REFUSED,
                say("Session {number} has nothing to copy: {reason}", number=number, reason=str(exc)),
                error=True,
            )
            return False
        payload = state.pop("payload")
        state = copy.deepcopy(state)  # nothing of the student's scene is shared but what it was handed
        state["payload"] = payload
        camera = seat.client.camera
        view: tuple[list[float], list[float]] | None
        try:
            view = [float(x) for x in camera.position], [float(x) for x in camera.look_at]
        except AssertionError:  # the student's page has not reported a camera yet
            view = None
        own.restore(state)
        if view is not None:
            own.set_camera(*view)
        title = own.scene.title if own.scene is not None else state["scene"]
        self._tell(client, mark("Spotlight"), _spotlit(number, seat.name, title, own.time))
        return True

    def _spotlight_remote(self, client: viser.ClientHandle, number: int, pool: PoolTable) -> bool:
        """Spotlight of a session on another process of the pool: its state text asked through Redis (on
        this browser's callback thread, which waits for it), then opened in the teacher's own session as
        any state text is (checked whole: it came from outside this process)."""
        own = self.app.sessions.get(client.client_id)
        if own is None:
            self._tell(client, REFUSED, mark("Your own session is not ready yet: try again in a moment."), error=True)
            return False
        try:
            own.open_state(pool.ask(number))
        except ValueError as exc:
            self._tell(client, REFUSED, say("Session {number}: {reason}", number=number, reason=str(exc)), error=True)
            return False
        name = next((row.name for row in pool.remote_rows() if row.number == number), "")
        title = own.scene.title if own.scene is not None else mark("its scene")
        self._tell(client, mark("Spotlight"), _spotlit(number, name, title, own.time))
        return True

    def answer(self, number: int) -> str:
        """The state text (with its student's camera) of this process's session ``number``, for a Spotlight
        asked by a teacher on another process of the pool; the student's session is only read.

        Raises
        ------
        ValueError
            The session is not here (it left), is a teacher's, or has nothing a state text can carry.
        """
        with self._lock:
            found = next(((k, s) for k, s in self._seats.items() if s.number == number), None)
            teaching = found is not None and found[0] in self.teachers
        if teaching:
            raise ValueError("it is a teacher's view, not a student's")
        student = self.app.sessions.get(found[0]) if found is not None else None
        if found is None or student is None:
            raise ValueError("it is not connected (it may just have left)")
        try:
            return student.state_text(found[1].client)
        except AssertionError:  # the student's page has not reported a camera yet
            return student.state_text()

    # ------------------------------------------------------------------ messages
    def _tell(self, client: viser.ClientHandle, title: str, body: str, error: bool = False) -> None:
        """A notification to one browser, through its own session."""
        session = self.app.sessions.get(client.client_id)
        if session is not None:
            session.notify(title, body, client=client, error=error)

    def _safely(self, fn: Callable[[Any], object]) -> Callable[[Any], None]:
        return shielded_handler(fn, self._tell_error)

    def _tell_error(self, client: viser.ClientHandle | None, title: str, body: str) -> None:
        if client is not None:
            self._tell(client, title, body, error=True)
