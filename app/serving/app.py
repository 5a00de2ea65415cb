"""The App: one viser server, the simulations it serves, the real-time loop that drives them; and the export.

More in docs/app-notes.md (``app.serving.app``).
"""

from __future__ import annotations

import socket
import threading
import time
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import viser

from app.contracts import ClientId, Sessions
from app.guards.admission import Admission, Caps, install_admission
from app.guards.event_loop import confine_events
from app.guards.gate import install_gate
from app.guards.language import Languages
from app.guards.prop_hints import cache_prop_hints
from app.guards.responses import peer_address
from app.guards.serialize import serialize_once
from app.guards.tunnel import guard_tunnel
from app.guards.wire import departed
from app.language.catalogs import SOURCE
from app.language.words import mark, say
from app.panel import look
from app.panel.access import PAGE_WORDS
from app.panel.language_picker import LanguagePicker
from app.recording.export import EXPORT_FPS, Export, export_with, export_zip_with
from app.scenes.base import Scene
from app.serving.addresses import is_loopback
from app.serving.notices import NOTIFY_SECONDS
from app.serving.simulation import FPS, Simulation, first_scene
from app.teaching.class_questions import ClassQuestions
from app.teaching.following import apply_step
from app.teaching.lectures import Step, read_lecture
from app.teaching.presenter import Classroom, check_pin, new_pin
from app.teaching.states import parse_state
from app.teaching.teacher import TeacherDesk
from app.teaching.voters import Voters
from physics.integrators.warm import warm

__all__ = ["App", "export", "export_zip"]

NETWORK_SHARE = 0.3
"""Under load, the loop rests this fraction of its busy time between ticks: viser's event loop thread
serializes and sends the frames meanwhile (one GIL between them). Measured by benchmarks/serve.py."""


class App:
    """The app: the viser server, its simulations and the real-time loop that drives them.

    Three ways to serve. By default every browser sees and drives one shared simulation. In presenter
    mode (the default on a non-loopback host) the shared simulation is the lecture: every browser follows
    it read-only until it enters the PIN, and may explore a copy of its own (:mod:`app.teaching.presenter`;
    the copies are in ``app.sessions``). With ``private=True`` every browser gets its own simulation when it
    connects (``app.sessions``, by client id), freed when it leaves; there is no shared one.

    Parameters
    ----------
    host, port : str, int
        Where to serve (default http://127.0.0.1:8080).
    scene : str, optional
        Name of the first scene (default: the first in the picker).
    start_loop : bool
        Start the real-time loop thread (tests and the benchmark drive :meth:`frame` themselves).
    verbose : bool
        Let viser print its banner.
    fps : float
        Frames per second of the loop.
    share : bool
        Show viser's share button, which can publish the server on a public tunnel (off by default).
    dark : bool
        The dark look (``--dark``), for a dark lecture room.
    projector : bool
        Start in projector mode (``--projector``; :meth:`Simulation.set_projector`): the lecture's (every
        follower sees it) or, in private mode, every browser's own at first.
    private : bool
        One simulation per browser instead of one for all.
    presenter : bool, optional
        Presenter mode; default: on when ``host`` is not a loopback address and ``private`` is off.
    pin : str, optional
        The presenter PIN (4 to 32 letters or digits); default: six random digits, in ``app.pin``. With
        ``private=True``, the teacher PIN: given, it opens the teacher's view of the sessions
        (:mod:`app.teaching.teacher`, ``app.teacher``); not given, there is no teacher's view.
    state : str, optional
        A state text (:mod:`app.teaching.states`, the panel's "Copy state") to start from; in private mode
        every browser's session starts from it. A bad text raises ValueError before the server starts.
    lecture : str, optional
        A lecture file, by path or by name in ``lectures/`` (:mod:`app.teaching.lectures`); every step is
        checked before the server serves (ValueError naming the step and the key). In private mode every
        browser follows it on its own.
    answers : str or Path, optional
        Presenter mode: a CSV file rewritten with every class question's counts and times whenever a vote
        closes (``--export-answers``; :mod:`app.teaching.class_questions`, in ``app.questions``).
    caps : Caps, optional
        Connections and sessions per address and per process (:class:`app.guards.admission.Caps`; the
        defaults suit a lecture hall of 300).
    """

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        scene: str | None = None,
        *,
        start_loop: bool = True,
        verbose: bool = False,
        fps: float = FPS,
        share: bool = False,
        dark: bool = False,
        projector: bool = False,
        private: bool = False,
        presenter: bool | None = None,
        pin: str | None = None,
        state: str | None = None,
        lecture: str | None = None,
        answers: str | Path | None = None,
        caps: Caps | None = None,
        lang: str = SOURCE,
    ) -> None:
        if state is not None:
            scene = parse_state(state)["scene"]  # refused here, before anything starts
        self._state_text = state
        self._lecture = read_lecture(lecture) if lecture is not None else None
        self._first, _ = first_scene(scene)
        if presenter is None:
            presenter = not private and not is_loopback(host)
        if presenter and private:
            raise ValueError("choose presenter mode or private sessions, not both")
        if answers is not None and not presenter:
            raise ValueError("class questions are asked in presenter mode: --export-answers needs --presenter")
        self.pin = check_pin(pin) if pin is not None else new_pin()
        self.fps, self.share, self.dark, self.private = float(fps), bool(share), bool(dark), bool(private)
        self.projector = bool(projector)
        server = viser.ViserServer(host=host, port=port, verbose=verbose)
        confine_events(server)
        self.gate = install_gate(server)  # only the message types a page sends reach viser
        # Checked first, as a websocket opens: connections and sessions per address and per process.
        self.admission = install_admission(server, Admission(caps or Caps(), sessions_per_connection=private))
        # Before anything is sent: each browser's messages pass through its language on the way out.
        self.languages = Languages(server, lang, PAGE_WORDS)
        serialize_once()  # a message to many browsers is serialized once (presenter and shared mode)
        cache_prop_hints()  # a handle's type hints are looked up once per kind of handle, not per handle
        self.server = server
        self.host, self.port = host, server.get_port()
        self.voters = Voters(server)  # one identity per browser, kept across reconnects (PINs, votes)
        self.languages.identity = self.voters.browser  # a browser's choice of language, kept likewise
        self.sessions: Sessions[Simulation] = Sessions()
        self.shared: Simulation | None = None
        self.classroom: Classroom | None = None
        self.teacher: TeacherDesk | None = None
        self.questions: ClassQuestions | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        if presenter:
            self.classroom = Classroom(self, self.pin, self._copy_for)
        guard_tunnel(server, share=share, permit=self.refusal, refuse=self._refuse)
        try:
            if self.private:
                look.configure(server.gui, share=share, dark=dark)
                if self._lecture is not None:  # checked once, on a simulation nobody sees, before serving
                    probe = self._simulation(server)
                    try:
                        probe.load_lecture(self._lecture)
                    finally:
                        probe.close()
                if pin is not None:
                    self.teacher = TeacherDesk(self, self.pin)
                server.on_client_connect(self._open_session)
                server.on_client_disconnect(self._close_session)
            else:
                self.shared = self._simulation(server, refusal=self.refusal, shown_to=self._follows)
                if state is not None:
                    self.shared.open_state(state)
                if self.classroom is not None:
                    self.questions = ClassQuestions(self, answers)
                if self._lecture is not None:
                    self.shared.load_lecture(self._lecture)
                if self.projector:
                    self.shared.set_projector(True)
        except ValueError:
            server.stop()
            raise
        server.on_client_connect(self._greet)
        server.on_client_disconnect(lambda client: self.languages.forget(client.client_id))
        if start_loop:
            self.start()

    @classmethod
    def headless(cls, scene: str | None = None, *, state: str | None = None, preset: str | None = None) -> App:
        """An app on 127.0.0.1 that nobody watches and no loop drives, at a scene (and one of its presets)
        or at a state text: what an export records. ValueError for a bad scene, preset or state."""
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
            s.bind(("127.0.0.1", 0))
            port = int(s.getsockname()[1])
        app = cls(host="127.0.0.1", port=port, scene=scene, start_loop=False, presenter=False, state=state)
        if preset is not None:
            try:
                assert app.shared is not None and app.shared.scene is not None
                apply_step(app.shared, Step(scene=app.shared.scene.name, preset=preset))
            except ValueError:
                app.stop()
                raise
        return app

    @property
    def simulation(self) -> Simulation:
        """The shared simulation (shared and presenter mode); in private mode every browser has its own
        (``app.sessions``) and this raises AttributeError."""
        if self.shared is None:
            raise AttributeError("a private app has no shared simulation: each browser's is in app.sessions")
        return self.shared

    @property
    def scene(self) -> Scene | None:
        """The shared simulation's scene; None in private mode (every browser has its own)."""
        return self.shared.scene if self.shared is not None else None

    # The shared simulation driven from a script (examples/, benchmarks/, docs/screenshots.py): the few
    # calls a script needs, declared; anything else through ``app.simulation``.
    @property
    def time(self) -> float:
        """The shared simulation's time (s)."""
        return self.simulation.time

    @property
    def frames(self) -> int:
        """Frames the shared simulation has drawn."""
        return self.simulation.frames

    @property
    def messages(self) -> list[tuple[str, str]]:
        """The notifications the shared simulation has shown, (title, body), oldest first."""
        return self.simulation.messages

    def frame(self, wall_dt: float = 1.0 / FPS) -> bool:
        """Advance the shared simulation by ``wall_dt`` seconds of wall time and draw (:meth:`Simulation.frame`)."""
        return self.simulation.frame(wall_dt)

    def set_playing(self, playing: bool) -> None:
        self.simulation.set_playing(playing)

    def set_speed(self, speed: float) -> None:
        self.simulation.set_speed(speed)

    def switch_scene(self, name: str) -> None:
        self.simulation.switch_scene(name)

    def restart(self) -> None:
        self.simulation.restart()

    def go_to_step(self, index: int) -> None:
        self.simulation.go_to_step(index)

    def state_text(self) -> str:
        return self.simulation.state_text()

    def _simulation(self, target: viser.ViserServer | viser.ClientHandle, **kwargs: Any) -> Simulation:
        return Simulation(
            target,
            self._first,
            export=export_zip,
            fps=self.fps,
            share=self.share,
            dark=self.dark,
            language=self.languages.language,
            **kwargs,
        )

    def _greet(self, client: viser.ClientHandle) -> None:
        """A browser's panel gets its own Language dropdown (it reads the language its Accept-Language
        prefers if we speak it, else ``--lang``: :meth:`app.guards.language.Languages.language`); a private
        session's is added with its simulation."""
        if not self.private:
            LanguagePicker(client, self.languages)

    # ------------------------------------------------------------------ presenter mode
    @property
    def mode(self) -> str:
        """ "shared", "presenter" or "private"."""
        return "private" if self.private else ("presenter" if self.classroom is not None else "shared")

    def who(self, client_id: ClientId) -> tuple[str, str]:
        """A client's browser (its voter identity, kept across reconnects) and its network address: what the
        PIN limits count against (:class:`app.teaching.pin_gate.PinGate`)."""
        return self.voters.identity(client_id), peer_address(self.server, client_id) or f"connection {client_id}"

    def refusal(self, client_id: ClientId) -> str | None:
        """Why a browser may not drive the shared simulation (a follower in presenter mode), or None."""
        return self.classroom.refusal(client_id) if self.classroom is not None else None

    def _refuse(self, client_id: ClientId, reason: str) -> None:
        """Tell one browser it was refused, through the simulation it sees."""
        client = self.server.get_clients().get(client_id)
        simulation = self.sessions.get(client_id, self.shared)
        if client is None:
            return
        if simulation is not None:
            simulation.notify(mark("Refused"), reason, client=client, error=True)
        else:  # a private browser whose session is still being made: told all the same
            client.add_notification(mark("Refused"), reason, color="red", auto_close_seconds=NOTIFY_SECONDS)

    def _follows(self, client: viser.ClientHandle) -> bool:
        """Whether a browser is drawn the shared simulation (not one exploring a copy of its own)."""
        return self.classroom is None or not self.classroom.exploring(client.client_id)

    def _copy_for(self, client: viser.ClientHandle) -> Simulation:
        """A browser's own copy of the lecture, at the lecture's current state (presenter mode)."""
        assert self.shared is not None
        owners = list(self.sessions)
        refused = self.admission.session_refusal(client.client_id, owners)
        if refused is not None:
            raise ValueError(say("no copy of your own: {refused}", refused=refused))
        snapshot = self.shared.snapshot()
        copy = Simulation(
            client,
            snapshot["scene"],
            export=export_zip,
            fps=self.fps,
            share=self.share,
            dark=self.dark,
            language=self.languages.language,
        )
        copy.restore(snapshot)
        if self.shared.projector.on:  # the lecture's bar and panels leave with it (app.guards.broadcast)
            copy.projector.give_panel_back()
        if self.questions is not None:  # a question open on the lecture keeps its answer in the copy too
            copy.hold_back(self.questions.holding())
        return copy

    # ------------------------------------------------------------------ private sessions
    def _open_session(self, client: viser.ClientHandle) -> None:
        try:
            session = self._simulation(client)
            if self._state_text is not None:
                session.open_state(self._state_text)
            if self._lecture is not None:
                session.load_lecture(self._lecture, check=False)
            if self.projector:
                session.set_projector(True)
            # After the scene is built: its own controls (the teacher's parameters) are known without it.
            LanguagePicker(client, self.languages)
        except Exception:
            if departed(client):
                return  # it left while its session was being built
            raise
        self.sessions.put(client.client_id, session)
        if self.teacher is not None:
            self.teacher.joined(client, session)
        if departed(client):  # it left just now: its disconnect may have come before the line above
            self._close_session(client)

    def _close_session(self, client: viser.ClientHandle) -> None:
        # The browser has gone: its panel and nodes went with its connection; drop the simulation.
        self.sessions.pop(client.client_id)

    def simulations(self) -> list[Simulation]:
        """The simulations the loop drives: the shared one and one per browser that has its own."""
        own = self.sessions.values()
        return own if self.shared is None else [self.shared, *own]

    # ------------------------------------------------------------------ the loop
    def start(self) -> None:
        """Start the real-time loop thread (daemon), and compile the integrators' kernels beside it."""
        if self.teacher is not None:
            self.teacher.start()
        if self._thread is not None:
            return
        # numba compiles (or loads from its cache) in the background: a scene's first step never waits.
        threading.Thread(target=warm, name="rbl-warm-kernels", daemon=True).start()
        self._stop.clear()
        self._thread = threading.Thread(target=self.run, name="rbl-loop", daemon=True)
        self._thread.start()

    def run(self) -> None:
        """The real-time loop (the loop thread's body): a tick of every simulation per frame, until stopped."""
        period = 1.0 / self.fps
        last = due = time.perf_counter()
        while not self._stop.is_set():
            now = time.perf_counter()
            dt, last = now - last, now
            self._tick(dt)
            done = time.perf_counter()
            busy = done - now
            # Frames are due on a fixed schedule: a wake-up that came late (the GIL held by the network
            # thread, a busy machine) is made up by a shorter rest, not lost; a loop more than a frame
            # behind starts the schedule afresh rather than rushing frames out to catch up.
            due = max(due + period, done - period)
            # Under load (many private sessions) a tick takes longer than a frame: each session then
            # advances by the real elapsed time (the physics is exact at any step), and the loop leaves
            # the GIL to the network thread for a share of its own time, so that what was drawn is sent.
            self._stop.wait(max(due - done, NETWORK_SHARE * busy))

    def _tick(self, dt: float) -> None:
        """One frame of every simulation. A function of its own so that its loop variable dies with it: a
        variable of :meth:`run` would keep the last session of a departed browser alive."""
        for simulation in self.simulations():
            try:
                simulation.tick(dt)
            except Exception:  # noqa: BLE001 - the loop never dies, and one session cannot stop another
                traceback.print_exc()

    def stop(self) -> None:
        """Stop the loop and the server."""
        if self.teacher is not None:
            self.teacher.stop()
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
            self._thread = None
        if self.questions is not None:
            self.questions.write()
        self.server.stop()

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}"


def export(
    scene: str | None,
    out: str | Path,
    seconds: float,
    *,
    preset: str | None = None,
    state: str | None = None,
    fps: float = EXPORT_FPS,
    progress: Callable[[int, int], None] | None = None,
    lang: str = SOURCE,
) -> Export:
    """Run a scene for ``seconds`` of simulated time without a browser and write the page, CSV and PNG
    (``rigid-body-lab export``; :func:`app.recording.export.export_with`, handed :meth:`App.headless`).

    Parameters
    ----------
    scene : str or None
        A scene name (``rigid-body-lab --scene``); None takes the state's scene.
    out : str or Path
        The directory to write (created if missing; files of the same names are replaced).
    seconds : float
        Simulated time to record (s), from 1/30 s to :data:`app.recording.export.MAX_SECONDS`.
    preset : str, optional
        One of the scene's presets, by its name in the panel.
    state : str, optional
        A state text (the panel's "Copy state"): its scene, controls, time and camera.
    fps : float
        Frames per simulated second (rows of the CSV, frames of the recording).
    progress : callable, optional
        Called as ``progress(frames done, frames in all)`` after every frame.
    lang : str
        The language of the page's words (``rigid-body-lab export --lang``): one of
        :data:`app.language.catalogs.LANGUAGES`, or the pseudo-locale.

    Raises
    ------
    ValueError
        A bad scene, preset, state, number of seconds or language, or a scene that failed while running
        (named with its time); nothing is written then.
    """
    return export_with(
        _headless_simulation, scene, out, seconds, preset=preset, state=state, fps=fps, progress=progress, lang=lang
    )


def export_zip(
    state: str, seconds: float, progress: Callable[[int, int], None] | None = None, lang: str = SOURCE
) -> bytes:
    """The files :func:`export` writes for a state text, as one zip archive (the panel's Export button, in
    the language of the browser that pressed it; :func:`app.recording.export.export_zip_with`)."""
    return export_zip_with(_headless_simulation, state, seconds, progress, lang)


@contextmanager
def _headless_simulation(scene: str | None, *, state: str | None, preset: str | None) -> Iterator[Simulation]:
    """The shared simulation of :meth:`App.headless`, its app stopped on leaving: what an export records."""
    app = App.headless(scene, state=state, preset=preset)
    try:
        assert app.shared is not None
        yield app.shared
    finally:
        app.stop()
