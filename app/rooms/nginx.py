"""nginx in front of the rooms: its configuration, and where its binary is.

:func:`rooms_conf` is the ``http { }`` part (it can go into Debian's ``/etc/nginx/conf.d/`` as it is);
:func:`nginx_conf` wraps it into a whole configuration whose pid file, logs and temporary files are
relative to nginx's prefix (``nginx -p DIR -c DIR/nginx.conf``), so it runs without touching the
system's nginx.

How a room is served (viser 1.1.1's page opens its websocket at its own address without the trailing
slash, with the subprotocol ``viser-v1.1.1``):

* ``/NAME/`` and everything under it go to the room's backends with the prefix stripped (``/NAME/x`` ->
  ``/x``), so the page's relative addresses work unchanged; the app never learns its prefix.
* ``/NAME`` is the page's websocket: an upgrade goes to ``/`` of the room, anything else is redirected to
  ``/NAME/`` (a relative redirect, right behind any further proxy).
* Websockets are upgraded (``Upgrade``/``Connection`` passed on, HTTP/1.1), ``Sec-WebSocket-Protocol``
  is passed through both ways like any header, and idle timeouts are an hour (a lecture).
* A private pool spreads browsers fairly and keeps each on its process. A first visit (no room cookie,
  or one naming no process of the pool) goes to the pool's least-loaded process (``least_conn``, its
  counts shared by nginx's workers through a ``zone``: a browser's websocket is its one long connection),
  and the response sets the room's cookie to that process's number. Every later request with the cookie
  goes to that process, from any address, so a lecture hall behind one NAT address still spreads. When
  that process is down, the request falls back to the least-loaded living one (``error_page 502``) and
  the cookie is set anew: a process that dies loses only its own browsers, which land on the survivors.
  A process that refuses connections is skipped for a few seconds (``max_fails=1``).
* ``/`` is the landing page (:mod:`app.rooms.landing`); anything else is 404.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from app.language.catalogs import LANGUAGES, SOURCE
from app.rooms.config import Department, Room
from app.rooms.landing import landing_html

__all__ = ["NGINX_INSTALL", "NginxMissing", "find_nginx", "nginx_conf", "nginx_command", "rooms_conf"]

NGINX_INSTALL = "sudo apt-get install nginx"
"""The line that installs the proxy on Debian or Ubuntu."""

SBIN = ("/usr/sbin", "/usr/local/sbin", "/sbin")
"""Where Debian puts nginx, often not on a user's PATH."""

FAIL_TIMEOUT = 3
"""Seconds a pool process that refused a connection is skipped before nginx tries it again."""

IDLE_TIMEOUT = 3600
"""Seconds a quiet websocket is kept open (a paused lecture sends nothing)."""

BACKEND_HEADER = "X-Room-Backend"
"""Response header naming the process that answered (local runs only: tests and benchmarks read it)."""


class NginxMissing(RuntimeError):
    """nginx is not installed (or not where the caller said): the message has the line to install it."""


def find_nginx(explicit: str | None = None, search_path: str | None = None) -> str:
    """The nginx binary: ``explicit`` if given, else the first on ``search_path`` (default: ``$PATH`` and
    Debian's sbin folders); :class:`NginxMissing` with the ``apt-get install`` line when there is none."""
    if explicit is not None:
        if os.path.isfile(explicit) and os.access(explicit, os.X_OK):
            return explicit
        raise NginxMissing(f"nginx not found at {explicit}; install it with: {NGINX_INSTALL}")
    if search_path is None:
        search_path = os.pathsep.join([os.environ.get("PATH", ""), *SBIN])
    found = shutil.which("nginx", path=search_path)
    if found is None:
        raise NginxMissing(f"nginx not found (the rooms' proxy); install it with: {NGINX_INSTALL}")
    return found


def nginx_command(nginx: str, prefix: str | Path, *, test: bool = False) -> list[str]:
    """The command that runs (or with ``test`` checks) the configuration written into ``prefix``, in the
    foreground, its startup errors into the prefix's log too."""
    prefix = Path(prefix).resolve()
    command = [nginx, "-p", f"{prefix}/", "-c", str(prefix / "nginx.conf"), "-e", str(prefix / "logs" / "error.log")]
    return [*command, "-t", "-q"] if test else [*command, "-g", "daemon off;"]


def nginx_conf(workers: str = "auto") -> str:
    """A whole nginx configuration around ``rooms.conf`` (same folder): pid file, logs and temporary files
    under nginx's prefix (``-p``), for running it beside (or instead of) the system's nginx."""
    return f"""# Rigid Body Lab rooms: a whole nginx configuration (written by `rigid-body-lab rooms --write`).
# Run: nginx -p THIS_FOLDER/ -c THIS_FOLDER/nginx.conf -g 'daemon off;'   (paths below: under -p)
worker_processes {workers};
worker_rlimit_nofile 8192;
pid logs/nginx.pid;
error_log logs/error.log notice;

events {{
    worker_connections 4096;  # two per websocket (browser side, process side)
}}

http {{
    client_body_temp_path temp/body;
    proxy_temp_path temp/proxy;
    fastcgi_temp_path temp/fastcgi;
    uwsgi_temp_path temp/uwsgi;
    scgi_temp_path temp/scgi;
    include rooms.conf;
    access_log logs/access.log rbl;  # the format is defined in rooms.conf
}}
"""


def rooms_conf(department: Department, *, backend_header: bool = False) -> str:
    """The ``http { }`` part: log format, maps, one upstream per room, and the server on ``listen``.

    ``backend_header``: every response names the process that answered (:data:`BACKEND_HEADER`), for a
    local run's tests; a deployment leaves it off (it would show the backends' addresses).
    """
    lines = [
        f"# Rigid Body Lab rooms from {department.source} (written by `rigid-body-lab rooms`; edit that file).",
        "log_format rbl '$remote_addr [$time_local] \"$request\" $status $body_bytes_sent $request_time '",
        "               'upstream=$upstream_addr room_cookie=$rbl_room_cookie';",
        "",
        "# A websocket upgrade passes Upgrade/Connection on; a plain request closes the backend connection.",
        "map $http_upgrade $rbl_connection {",
        "    default upgrade;",
        '    ""      close;',
        "}",
        "",
        "# The landing page's language: the first the browser asks for, if the app speaks it (else English).",
        "map $http_accept_language $rbl_lang {",
        f"    default {SOURCE};",
        *(f"    ~*^{lang}\\b {lang};" for lang in LANGUAGES if lang != SOURCE),
        "}",
        "",
    ]
    private = [room for room in department.rooms if room.mode == "private"]
    lines += _cookie_maps(private)
    for room in department.rooms:
        lines += _upstream(room)
    lines += _server(department, backend_header)
    return "\n".join(lines) + "\n"


def _cookie_maps(private: list[Room]) -> list[str]:
    """Per pool: where the room's cookie routes a request (a process of the pool by its number, or the
    least-loaded one), and the Set-Cookie header naming the process that answered when the browser's cookie
    does not already name it (empty: nginx sends no header)."""
    lines = ["# The room's cookie as the access log shows it (private pools only)."]
    lines += ["map $request_uri $rbl_room_cookie {", '    default "-";']
    for room in private:
        lines += [f"    ~^/{room.name}([/?]|$) $cookie_{room.ident};"]
    lines += ["}", ""]
    for room in private:
        ident = room.ident
        lines += [
            f"# {room.name}: a browser stays on the process its cookie {ident} names; a first visit (or a cookie",
            "# naming no process of the pool) goes to the least-loaded one.",
            f"map $cookie_{ident} ${ident}_route {{",
            f"    default {ident};",
            *[f'    "{k}" {ident}_{k};' for k in range(len(room.backends))],
            "}",
            f"# The process that answered (the last of $upstream_addr), named in {ident} unless it is already.",
            f'map "$cookie_{ident}@$upstream_addr" ${ident}_set_cookie {{',
            '    default "";',
        ]
        for k, backend in enumerate(room.backends):
            address = _regex(backend.address)
            lines.append(f'    "~^{k}@(.*[ ,:] )?{address}$" "";')
        for k, backend in enumerate(room.backends):
            cookie = f"{ident}={k}; Path=/{room.name}; HttpOnly; SameSite=Lax"
            lines.append(f'    "~(^|@|[ ,:] ){_regex(backend.address)}$" "{cookie}";')
        lines += ["}", ""]
    return lines


def _regex(address: str) -> str:
    """``address`` (host:port) as a literal in an nginx regular expression."""
    return "".join(f"\\{c}" if c in ".[]()" else c for c in address)


def _upstream(room: Room) -> list[str]:
    lines = [f"upstream {room.ident} {{"]
    if room.mode == "private" and len(room.backends) > 1:
        # The least-loaded process for a first visit; the counts shared by every nginx worker.
        lines += [f"    zone {room.ident} 64k;", "    least_conn;"]
        options = f" max_fails=1 fail_timeout={FAIL_TIMEOUT}s"
    else:
        options = ""  # one process: nginx never marks the only server down
    lines += [f"    server {backend.address}{options};" for backend in room.backends]
    lines += ["}", ""]
    if room.mode == "private" and len(room.backends) > 1:
        # One group per process, for the browsers its number routes there (a name, not an address, so that
        # proxy_pass with a variable needs no resolver for hosts given by name).
        for k, backend in enumerate(room.backends):
            lines += [f"upstream {room.ident}_{k} {{", f"    server {backend.address};", "}", ""]
    return lines


def _landing(department: Department, lang: str) -> str:
    page = landing_html(department, lang)
    for forbidden in ("'", "\\", "$"):  # the page is one single-quoted nginx string without variables
        if forbidden in page:
            raise ValueError(f"the landing page contains {forbidden!r}, which an nginx string cannot carry")
    return page


def _server(department: Department, backend_header: bool) -> list[str]:
    page = _landing(department, SOURCE)
    # One page per language, chosen by $rbl_lang (an if that only returns: nginx's safe use of if).
    translated = [
        f"        if ($rbl_lang = {lang}) {{ return 200 '{_landing(department, lang)}'; }}"
        for lang in LANGUAGES
        if lang != SOURCE
    ]
    lines = [
        "server {",
        f"    listen {department.listen};",
        "    server_name _;",
        "    absolute_redirect off;  # /NAME -> /NAME/ stays right behind any further proxy",
        "    proxy_http_version 1.1;",
        "    proxy_set_header Upgrade $http_upgrade;",
        "    proxy_set_header Connection $rbl_connection;",
        "    proxy_set_header Host $host;",
        "    proxy_set_header X-Real-IP $remote_addr;",
        "    proxy_set_header X-Forwarded-For $proxy_add_x_forwarded_for;",
        "    proxy_set_header X-Forwarded-Proto $scheme;",
        "    proxy_buffering off;  # frames go to the browser as they come",
        f"    proxy_read_timeout {IDLE_TIMEOUT}s;",
        f"    proxy_send_timeout {IDLE_TIMEOUT}s;",
        "    proxy_connect_timeout 5s;",
        "",
        "    location = / {",
        "        default_type text/html;",
        "        add_header Cache-Control no-cache;",
        "        add_header Vary Accept-Language;",
        *translated,
        f"        return 200 '{page}';",
        "    }",
        "    location / {",
        "        return 404;",
        "    }",
    ]
    for room in department.rooms:
        lines += _room_locations(room, backend_header)
    return [*lines, "}"]


def _room_locations(room: Room, backend_header: bool) -> list[str]:
    """``/NAME`` (the websocket) and ``/NAME/`` (the page and its files) of one room, prefix stripped."""
    headers = []
    if backend_header:
        headers.append(f"        add_header {BACKEND_HEADER} $upstream_addr always;")
    redirect = ['        if ($http_upgrade = "") {', f"            return 301 /{room.name}/;", "        }"]
    comment = f"    # {room.name}: {room.mode}, {len(room.backends)} process(es)"
    if room.mode != "private" or len(room.backends) == 1:
        if room.mode == "private":
            headers.append(f"        add_header Set-Cookie ${room.ident}_set_cookie always;")
        return [
            "",
            comment,
            f"    location = /{room.name} {{",
            *redirect,
            f"        proxy_pass http://{room.ident}/;",
            *headers,
            "    }",
            f"    location /{room.name}/ {{",
            f"        proxy_pass http://{room.ident}/;",
            *headers,
            "    }",
        ]
    # A pool: proxied to the process the cookie names (a variable, so the prefix is stripped by a rewrite);
    # that process down, to the least-loaded living one.
    headers.append(f"        add_header Set-Cookie ${room.ident}_set_cookie always;")
    fallback = f"@{room.ident}_any"
    routed = [f"        proxy_pass http://${room.ident}_route;", f"        error_page 502 504 = {fallback};", *headers]
    return [
        "",
        comment,
        f"    location = /{room.name} {{",
        *redirect,
        "        rewrite ^ / break;",
        *routed,
        "    }",
        f"    location /{room.name}/ {{",
        f"        rewrite ^/{room.name}/(.*)$ /$1 break;",
        *routed,
        "    }",
        f"    location {fallback} {{",
        f"        proxy_pass http://{room.ident};",
        *headers,
        "    }",
    ]
