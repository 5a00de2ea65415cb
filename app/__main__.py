"""The ``rigid-body-lab`` command: start the viser server and print the addresses to open.

``rigid-body-lab export --scene NAME [--preset P | --state TEXT] --seconds S --out DIR [--lang L]`` records a motion
without a browser instead (:mod:`app.recording.export`); ``rigid-body-lab rooms ROOMS.toml [--write DIR]`` serves a
department's rooms behind nginx (:mod:`app.rooms`).
"""

from __future__ import annotations

import argparse
import os
import re
import time


def plain(doc: str) -> str:
    """A docstring as a terminal shows it: ``code`` and :role:`name` markup written as plain text."""
    return re.sub(r":\w+:`~?([^`]+)`", r"\1", doc).replace("``", "")


def export_main(argv: list[str]) -> None:
    """``rigid-body-lab export``: write DIR/index.html, DIR/NAME.csv and DIR/NAME.png."""
    from app.language.catalogs import LANGUAGES, PSEUDO
    from app.recording.export import EXPORT_FPS, MAX_SECONDS, terminal_progress
    from app.scenes import scene_names
    from app.serving.app import export

    parser = argparse.ArgumentParser(
        prog="rigid-body-lab export",
        description="Record a scene without a browser: a web page that plays it (index.html, viser's client "
        "with the recording), its quantities as CSV (first column t in s, units in the header) and a PNG of "
        "the last frame.",
    )
    parser.add_argument("--scene", default=None, choices=scene_names(), help="the scene (a --state names its own)")
    start = parser.add_mutually_exclusive_group()
    start.add_argument(
        "--preset",
        default=None,
        help="one of the scene's presets: its name in the panel, typed in ASCII in any case, or its start (loops)",
    )
    start.add_argument("--state", default=None, metavar="TEXT", help="a state text (the panel's “Copy state”)")
    parser.add_argument(
        "--seconds", type=float, required=True, help=f"simulated time to record, s (at most {MAX_SECONDS:g})"
    )
    parser.add_argument("--fps", type=float, default=EXPORT_FPS, help="frames (CSV rows) per simulated second")
    parser.add_argument("--out", required=True, help="the directory to write (created if missing)")
    parser.add_argument(
        "--lang",
        default="en",
        choices=(*LANGUAGES, PSEUDO),
        help="the language of the page's words (its scene's labels); the CSV's columns are symbols and units",
    )
    args = parser.parse_args(argv)
    if args.scene is None and args.state is None:
        parser.error("give --scene NAME (or --state TEXT)")
    try:
        written = export(
            args.scene,
            args.out,
            args.seconds,
            preset=args.preset,
            state=args.state,
            fps=args.fps,
            progress=terminal_progress,
            lang=args.lang,
        )
    except ValueError as exc:
        parser.error(str(exc))
    print(f"{written.frames} frames written:", flush=True)
    for path in (written.html, written.csv, written.png):
        print(f"  {path}", flush=True)


def main(argv: list[str] | None = None) -> None:
    import sys

    from app.language.catalogs import LANGUAGES, PSEUDO
    from app.scenes import scene_names

    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["export"]:
        export_main(argv[1:])
        return
    if argv[:1] == ["rooms"]:
        from app.rooms.cli import main as rooms_main

        raise SystemExit(rooms_main(argv[1:]))

    parser = argparse.ArgumentParser(prog="rigid-body-lab", description=plain(__doc__ or ""))
    parser.add_argument("--host", default="127.0.0.1", help="127.0.0.1 (default) or 0.0.0.0 for a classroom LAN")
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--scene", default=None, choices=scene_names(), help="scene shown first")
    parser.add_argument(
        "--share",
        action="store_true",
        help="show viser's share button, which can publish this server on a public tunnel (off by default)",
    )
    parser.add_argument("--dark", action="store_true", help="a dark look, for a dark lecture room")
    parser.add_argument(
        "--lang",
        default="en",
        choices=(*LANGUAGES, PSEUDO),
        help="the language of a browser that prefers none we speak (each browser may choose its own in the "
        "panel; en-XA: the pseudo-locale, for translators and tests)",
    )
    parser.add_argument(
        "--projector",
        action="store_true",
        help="start in projector mode: the panel a slim bar, the step's caption and the scene's key plot large "
        "(the panel's Projector button switches it)",
    )
    parser.add_argument(
        "--private",
        action="store_true",
        help="every browser gets its own simulation (a lab session or a homework server)",
    )
    parser.add_argument(
        "--presenter",
        action="store_true",
        help="presenter mode on 127.0.0.1 too (it is the default for any other --host): browsers follow "
        "the lecture read-only until they enter the PIN",
    )
    parser.add_argument(
        "--shared",
        action="store_true",
        help="one simulation every browser drives, on any --host (the default on 127.0.0.1 only)",
    )
    parser.add_argument(
        "--pin",
        default=os.environ.get("RBL_PIN") or None,  # app.rooms.config.PIN_VARIABLE: kept off the command line
        help="presenter PIN, 4 to 32 letters or digits (default: the environment's RBL_PIN, else random); with "
        "--private, the teacher PIN that opens the table of every session and Spotlight (without it, --private "
        "has no teacher's view)",
    )
    parser.add_argument(
        "--state", default=None, metavar="TEXT", help="start from a state text (the panel's “Copy state”)"
    )
    parser.add_argument(
        "--lecture",
        default=None,
        metavar="FILE",
        help="follow a lecture: a TOML file of steps, or the name of one in lectures/ (e.g. rigid-body-motion)",
    )
    parser.add_argument(
        "--export-answers",
        default=None,
        metavar="FILE",
        help="presenter mode: write every class question's counts and times to this CSV file whenever a vote "
        "closes (and when the server stops)",
    )
    parser.add_argument(
        "--max-connections", type=int, default=400, metavar="N", help="browsers connected at once (default 400)"
    )
    parser.add_argument(
        "--max-per-address",
        type=int,
        default=4,
        metavar="N",
        help="browsers connected at once from one address (default 4)",
    )
    parser.add_argument(
        "--max-sessions",
        type=int,
        default=300,
        metavar="N",
        help="simulations of their own at once: private sessions or explorers' copies (default 300)",
    )
    parser.add_argument(
        "--max-sessions-per-address",
        type=int,
        default=4,
        metavar="N",
        help="simulations of their own at once for one address (default 4)",
    )
    parser.add_argument(
        "--max-opens-per-minute",
        type=int,
        default=10,
        metavar="N",
        help="new connections one address may open a minute, after a first burst (default 10)",
    )
    args = parser.parse_args(argv)

    from app.guards.admission import Caps
    from app.serving.addresses import is_loopback, urls
    from app.serving.app import App
    from app.teaching.presenter import check_pin

    if args.pin is not None:
        try:
            check_pin(args.pin)
        except ValueError as exc:
            parser.error(str(exc))
    if sum((args.private, args.presenter, args.shared)) > 1:
        parser.error("choose one of --presenter, --private and --shared")
    if args.state is not None:
        from app.teaching.states import parse_state

        try:
            parse_state(args.state)
        except ValueError as exc:
            parser.error(f"--state: {exc}")
    if args.lecture is not None:
        from app.teaching.lectures import read_lecture

        try:
            read_lecture(args.lecture)
        except ValueError as exc:
            parser.error(f"--lecture: {exc}")
    presenter = True if args.presenter else (False if args.shared else None)
    if args.export_answers is not None:
        from pathlib import Path

        folder = Path(args.export_answers).resolve().parent
        if not folder.is_dir() or not os.access(folder, os.W_OK):
            parser.error(f"--export-answers: cannot write in {folder}")
    try:
        app = App(
            host=args.host,
            port=args.port,
            scene=args.scene,
            share=args.share,
            dark=args.dark,
            projector=args.projector,
            private=args.private,
            presenter=presenter,
            pin=args.pin,
            state=args.state,
            lecture=args.lecture,
            answers=args.export_answers,
            lang=args.lang,
            caps=Caps(
                args.max_connections,
                args.max_per_address,
                args.max_sessions,
                args.max_sessions_per_address,
                args.max_opens_per_minute,
            ),
        )
    except ValueError as exc:  # a lecture step or a state the scene refuses, a cap out of range
        parser.error(str(exc))
    if is_loopback(args.host):
        print(f"Rigid Body Lab serving on {app.url}", flush=True)
    else:
        found = urls(args.host, app.port)
        print("Rigid Body Lab serving on the local network; students open:", flush=True)
        for url in found or [f"http://<this machine's IP address>:{app.port}"]:
            print(f"  {url}", flush=True)
    if app.mode == "presenter":
        print(
            f"Presenter PIN: {app.pin}  (type it in the panel's “Presenter PIN” box to drive the lecture)", flush=True
        )
    else:
        print(f"Mode: {app.mode} (every browser {'has its own' if app.private else 'drives the one'} simulation)")
    if app.teacher is not None:
        print(
            "Teacher's view: type the --pin in the panel's “Teacher PIN” box to open the table of sessions", flush=True
        )
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        app.stop()


if __name__ == "__main__":
    main()
