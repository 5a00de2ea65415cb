"""The ``rigid-body-lab`` command: start the viser server and print its address."""

from __future__ import annotations

import argparse
import time


def main(argv: list[str] | None = None) -> None:
    from app.scenes import scene_names

    parser = argparse.ArgumentParser(prog="rigid-body-lab", description=__doc__)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--scene", default=None, choices=scene_names(), help="scene shown first")
    args = parser.parse_args(argv)

    from app.server import App

    app = App(host=args.host, port=args.port, scene=args.scene)
    print(f"Rigid Body Lab serving on {app.url}", flush=True)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        app.stop()


if __name__ == "__main__":
    main()
