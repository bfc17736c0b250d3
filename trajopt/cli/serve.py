"""``mpa serve``: a local web explorer of tracks, domains and motions (:mod:`trajopt.web`).

``mpa serve [--port 8000] [--host 127.0.0.1] [--track ... | --graph FILE] [--no-browser]`` listens on
``--host:--port`` (``127.0.0.1`` by default: only this machine; ``--port 0`` picks a free port), prints the
address, opens it in the default browser unless ``--no-browser`` and serves until Ctrl-C (exit 130, one line
``interrupted``). It needs the optional extra ``[serve]`` (Starlette, uvicorn); without it: exit 2, one line
naming ``pip install 'lollipop-mpa[serve]'``. A port that cannot be opened is exit 2 too.
"""

from __future__ import annotations

import argparse
import importlib.util
import socket
import sys
import threading
import webbrowser
from pathlib import Path
from typing import Any

from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError

__all__ = ["register", "validate_serve_extra"]


def validate_serve_extra() -> None:
    """Raise :class:`InvalidInputError` naming the extra to install when Starlette or uvicorn is missing."""
    missing = [m for m in ("starlette", "uvicorn") if importlib.util.find_spec(m) is None]
    if missing:
        raise InvalidInputError(
            f"mpa serve needs the optional dependencies starlette and uvicorn ({', '.join(missing)} not installed): "
            "pip install 'lollipop-mpa[serve]'"
        )


#: Deprecated name of :func:`validate_serve_extra` (warns).
check_serve_extra = deprecated_alias(validate_serve_extra, "check_serve_extra")


def _initial(args: argparse.Namespace) -> dict[str, Any]:
    """The track the page opens with (checked now, so a bad one is exit 2 before the server starts)."""
    from mpa.graph_track import GraphTrack
    from mpa.tracks import make_track

    if args.graph is not None and args.track is not None:
        raise InvalidInputError(f"both --track {args.track} and --graph {args.graph} given, expected one of them")
    if args.graph is not None:
        track = GraphTrack.from_file(args.graph, getattr(args, "level", None), getattr(args, "nav_graph", None))
        return {"layout": track.to_dict(), "name": Path(args.graph).stem}
    t = make_track(args.track or "lollipop", args.stick, args.loop)
    return dict(t.to_dict())


def _listen(host: str, port: int) -> socket.socket:
    if not 0 <= port <= 65535:
        raise InvalidInputError(f"--port is {port}, expected an integer in [0, 65535]")
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except socket.gaierror as exc:
        raise InvalidInputError(f"--host is {host!r}: {exc.strerror}, expected an address of this machine") from None
    family, _, _, _, addr = infos[0]
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(addr)
        sock.listen(128)
    except OSError as exc:
        sock.close()
        reason = exc.strerror or type(exc).__name__
        raise InvalidInputError(f"--port {port}: cannot listen on {host}:{port}: {reason}") from None
    return sock


def _open_browser(url: str) -> None:
    """Open ``url`` in the default browser; without one (a headless machine) say so on stdout, one line."""
    try:
        opened = webbrowser.open(url)
    except webbrowser.Error:
        opened = False
    if not opened:
        print(f"mpa serve: no browser to open here, open {url} yourself", flush=True)


def _cmd_serve(args: argparse.Namespace) -> int:
    validate_serve_extra()
    initial = _initial(args)
    import uvicorn

    from trajopt.web.app import create_app

    sock = _listen(args.host, args.port)
    port = sock.getsockname()[1]
    shown = f"[{args.host}]" if ":" in args.host else args.host
    url = f"http://{shown}:{port}/"
    config = uvicorn.Config(create_app(initial), log_level="warning", access_log=False, lifespan="off")
    server = uvicorn.Server(config)
    print(f"mpa serve: {url} (Ctrl-C stops)", flush=True)
    if not args.no_browser:
        opener = threading.Timer(0.5, _open_browser, args=(url,))
        opener.daemon = True
        opener.start()
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
    if server.should_exit:  # uvicorn caught Ctrl-C / SIGTERM and shut down
        raise KeyboardInterrupt
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``serve`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = sub.add_parser("serve", help="a local web page to drag the robots and watch domains, plans and motions")
    p.add_argument("--port", type=int, default=8000, help="port to listen on (default 8000; 0: any free port)")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    p.add_argument("--track", choices=["interval", "circle", "lollipop"], default=None, help="open with this track")
    p.add_argument("--stick", type=float, default=None, help="stick length ℓ in metres (default 1)")
    p.add_argument("--loop", type=float, default=None, help="loop circumference c in metres (default 1)")
    p.add_argument(
        "--graph",
        metavar="FILE",
        default=None,
        help="open with this layout (our JSON, an Open-RMF building map or navigation graph) instead of --track",
    )
    from trajopt.cli.common import add_map_arguments

    add_map_arguments(p)
    p.add_argument("--no-browser", action="store_true", help="do not open the page in the default browser")
    p.set_defaults(func=_cmd_serve)


if __name__ == "__main__":  # pragma: no cover
    sys.exit("run as: mpa serve")
