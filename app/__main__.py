"""The ``rigid-body-lab`` command: start the viser server and print its address."""

from __future__ import annotations

import argparse
import time


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="rigid-body-lab", description=__doc__)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--scene", default=None)
    args = parser.parse_args(argv)

    import viser

    server = viser.ViserServer(host=args.host, port=args.port)
    print(f"Rigid Body Lab serving on http://{args.host}:{args.port}", flush=True)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        server.stop()


if __name__ == "__main__":
    main()
