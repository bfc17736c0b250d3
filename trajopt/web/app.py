"""The web application of ``mpa serve`` (Starlette): the page, its static files and the JSON API.

Routes:

==========================  ===============================================================================
route                       answer
==========================  ===============================================================================
``GET /``                   the page (``static/index.html``)
``GET /static/...``         its script and style (shipped in the package; no network access needed)
``GET /api/config``         the track the server was started with, the example layouts' names, the defaults
``GET /api/examples/NAME``  an example layout (by name only: no path reaches the file system)
``POST /api/plan``          :func:`trajopt.web.api.plan_answer`: what ``mpa plan --json`` prints
``POST /api/trajectory``    :func:`trajopt.web.api.trajectory_answer`: ``{"summary": ..., "csv": ...}``
``POST /api/track``         :func:`trajopt.web.api.track_answer`: the track drawn to scale
``POST /api/cspace``        :func:`trajopt.web.api.cspace_answer`: domains of every start for the goal
==========================  ===============================================================================

Errors: 400 ``{"error": ...}`` (bad input, a malformed body), 413 ``{"error": ...}`` (a body over
:data:`trajopt.web.api.MAX_BODY_BYTES`), 422 ``{"no_motion": ...}``, 404/405 ``{"error": ...}`` (an unknown route,
a wrong method); never a traceback.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import FileResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from mpa import defaults
from trajopt.web.api import (
    MAX_BODY_BYTES,
    answer,
    cspace_answer,
    example_layouts,
    plan_answer,
    track_answer,
    trajectory_answer,
)

__all__ = ["STATIC_DIR", "create_app"]

#: The page's files (package data).
STATIC_DIR = Path(__file__).resolve().parent / "static"


class _BodyError(Exception):
    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


def _json_response(status: int, obj: Any) -> Response:
    """A JSON response; a value JSON cannot hold (NaN, infinity) is an internal error, not a broken body."""
    try:
        text = json.dumps(obj, allow_nan=False, separators=(",", ":"))
    except (TypeError, ValueError) as exc:
        status, text = 500, json.dumps({"error": f"internal error: answer is not JSON: {exc}"})
    return Response(text, status_code=status, media_type="application/json")


async def _read_json(request: Request, limit: int) -> Any:
    """The request's JSON body, refused (413) past ``limit`` bytes and (400) when it is not JSON."""
    declared = request.headers.get("content-length")
    if declared is not None and declared.isdigit() and int(declared) > limit:
        raise _BodyError(413, f"request body is {int(declared)} bytes, expected at most {limit} bytes")
    chunks: list[bytes] = []
    size = 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise _BodyError(413, f"request body is over {limit} bytes, expected at most {limit} bytes")
        chunks.append(chunk)
    raw = b"".join(chunks)
    if not raw.strip():
        raise _BodyError(400, "request body is empty, expected a JSON object")
    try:
        return json.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as exc:
        raise _BodyError(
            400, f"request body is not JSON ({' '.join(str(exc).split())}), expected a JSON object"
        ) from None


def _api(fn: Callable[[Any], dict[str, Any]], limit: int) -> Callable[[Request], Any]:
    async def endpoint(request: Request) -> Response:
        try:
            body = await _read_json(request, limit)
        except _BodyError as exc:
            return _json_response(exc.status, {"error": str(exc)})
        status, obj = await run_in_threadpool(answer, fn, body)
        return _json_response(status, obj)

    return endpoint


def create_app(initial: dict[str, Any] | None = None, *, max_body_bytes: int = MAX_BODY_BYTES) -> Starlette:
    """The application.

    Parameters
    ----------
    initial : dict, optional
        The track the page opens with: ``{"track": kind, "stick": l, "loop": c}`` or
        ``{"layout": {...}, "name": str}`` (default: the paper's lollipop, ℓ = c = 1).
    max_body_bytes : int
        Largest request body accepted (bytes).
    """
    start = initial or {"track": "lollipop", "stick": 1.0, "loop": 1.0}
    examples = example_layouts()

    async def index(request: Request) -> Response:
        return FileResponse(STATIC_DIR / "index.html", media_type="text/html")

    async def config(request: Request) -> Response:
        return _json_response(
            200,
            {
                "initial": start,
                "examples": sorted(examples),
                "defaults": {
                    "clearance": defaults.CLEARANCE,
                    "vmax": defaults.VMAX,
                    "amax": defaults.AMAX,
                    "jmax": defaults.JMAX,
                    "rate": defaults.RATE,
                },
                "max_body_bytes": max_body_bytes,
            },
        )

    async def example(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in examples:
            return _json_response(404, {"error": f"example is {name!r}, expected one of {sorted(examples)}"})
        return _json_response(200, examples[name])

    routes = [
        Route("/", index),
        Route("/api/config", config),
        Route("/api/examples/{name}", example),
        Route("/api/plan", _api(plan_answer, max_body_bytes), methods=["POST"]),
        Route("/api/trajectory", _api(trajectory_answer, max_body_bytes), methods=["POST"]),
        Route("/api/track", _api(track_answer, max_body_bytes), methods=["POST"]),
        Route("/api/cspace", _api(cspace_answer, max_body_bytes), methods=["POST"]),
        Mount("/static", app=StaticFiles(directory=STATIC_DIR), name="static"),
    ]
    return Starlette(routes=routes, exception_handlers={HTTPException: _http_error, Exception: _server_error})


async def _http_error(request: Request, exc: Exception) -> Response:
    """An unknown route or a wrong method: ``{"error": ...}`` with the HTTP status (404, 405)."""
    status = exc.status_code if isinstance(exc, HTTPException) else 500
    detail = exc.detail if isinstance(exc, HTTPException) else str(exc)
    return _json_response(status, {"error": f"{request.method} {request.url.path}: {detail}"})


async def _server_error(request: Request, exc: Exception) -> Response:
    """A bug outside the API functions: one line, never a traceback."""
    return _json_response(500, {"error": f"internal error: {type(exc).__name__}: {' '.join(str(exc).split())}"})
