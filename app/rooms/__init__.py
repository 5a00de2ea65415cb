"""Rooms: a department's rooms behind nginx on one port (``rigid-body-lab rooms ROOMS.toml``).

One app process per presenter or shared room, a pool of processes per private room, each a separate
``python -m app`` process reached only through its command line; nginx routes ``/NAME/`` to its room.

* :mod:`app.rooms.config` — the rooms file, read and checked (refusals name the room and the key);
* :mod:`app.rooms.nginx` — nginx's configuration (prefix stripped, websockets, sticky private pools);
* :mod:`app.rooms.landing` — the landing page at ``/``;
* :mod:`app.rooms.supervisor` — start, watch, restart and stop the processes;
* :mod:`app.rooms.units` — systemd units for a deployment;
* :mod:`app.rooms.cli` — the command: run here in the foreground, or ``--write DIR``.
"""
