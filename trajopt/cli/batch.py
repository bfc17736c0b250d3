"""``mpa batch``: plan and verify every query of a CSV file on one layout, locally or on a Dask cluster.

::

    mpa batch --graph FILE --queries QUERIES.csv --out DIR [--clearance D] [--vmax V] [--amax A] [--jmax J]
              [--rate HZ] [--dask ADDRESS] [--workers N] [--setpoints] [--no-progress]

``QUERIES.csv`` has a header with (at least) the columns ``a_start, b_start, a_goal, b_goal``; each row is one
query, positions written as on the command line (``EDGE:OFFSET`` or a vertex name). Every query goes through the
whole pipeline (:class:`trajopt.generator.TrajectoryGenerator`: plan, timing, the verification gate); one result
row per query is written to ``DIR/results.csv`` (:data:`RESULT_COLUMNS`), in the order of the queries:

- ``row``: the query's number, 0 for the first row under the header;
- ``a_start, b_start, a_goal, b_goal``: the query as given;
- ``status``: ``ok``, ``no motion`` (valid query, no collision-free motion: ``message`` gives the reason),
  ``bad input`` (``message`` names the quantity, its value and what was expected) or ``internal error``;
- ``message``: empty when ``ok``;
- ``makespan`` (s, empty unless ``ok``), ``min_separation`` (m);
- ``route_a``, ``route_b``: each robot's edges in the order travelled, ``EDGE+`` along the edge's orientation,
  ``EDGE-`` against it, separated by spaces (empty for a robot that does not move);
- ``compute_time`` (s): planning, timing and verification of that query in its worker (not the file writing;
  the first query a worker runs also builds the layout's free space, which the others reuse).

With ``--setpoints`` the verified setpoints of each ``ok`` query are written to ``DIR/<row>/setpoints.csv``
(the columns of ``mpa trajectory --graph``). A bad row never stops the batch: its error is its result row.
The batch itself fails (exit 2, nothing written) only when the layout, the queries file or an option is wrong.

Where the queries run: in this process with ``--workers 1``; otherwise a local pool of ``--workers`` processes
(default: the number of cores, at most the number of queries); with ``--dask ADDRESS`` on the workers of an
existing Dask cluster (``dask.distributed.Client(ADDRESS)``; ``mpa`` and ``trajopt`` must be installed there).
A worker builds the planner of the layout once (:func:`run_query` keeps it) and reuses it for every query.
The graph planner searches with the compiled kernel (:mod:`trajopt.plan_kernel`, the same plans, node for node):
the batch compiles it, or loads it from numba's cache, once before its workers start.
A progress bar goes to stderr when stderr is a terminal (``--no-progress``: never).

``results.csv`` and every ``DIR/<row>/`` directory are written whole through a temporary file and
:func:`os.replace`; ``results.csv`` is written last, after every query has finished.
"""

from __future__ import annotations

import argparse
import csv
import io
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

from mpa.errors import InvalidInputError, MPAError, NoMotionError
from mpa.graph_track import GraphTrack
from trajopt.cli.common import (
    TRAJECTORY_DEFAULTS,
    add_clearance_argument,
    add_footprint_argument,
    add_map_arguments,
    graph_from_args,
    output_error,
    trajectory_options,
    validate_output_dir,
)

__all__ = [
    "QUERY_COLUMNS",
    "RESULT_COLUMNS",
    "STATUSES",
    "read_queries",
    "register",
    "results_csv_text",
    "run_batch",
    "run_query",
]

#: Columns every queries file must have (more are allowed and ignored).
QUERY_COLUMNS = ("a_start", "b_start", "a_goal", "b_goal")
#: Columns of ``DIR/results.csv``, in this order.
RESULT_COLUMNS = (
    "row",
    "a_start",
    "b_start",
    "a_goal",
    "b_goal",
    "status",
    "message",
    "makespan",
    "min_separation",
    "route_a",
    "route_b",
    "compute_time",
)
#: The values of the ``status`` column.
STATUSES = ("ok", "no motion", "bad input", "internal error")
#: Name of the results file in ``--out``.
RESULTS_FILE = "results.csv"
#: Name of the setpoints file in ``--out/<row>/``.
SETPOINTS_FILE = "setpoints.csv"

#: Seconds to wait for the Dask scheduler of ``--dask`` before giving up (exit 2).
DASK_TIMEOUT = 10.0

# A worker's generators, per configuration (layout, clearance, limits, rate): built once, reused by every query.
_GENERATORS: dict[tuple[Any, ...], Any] = {}


def read_queries(path: str | os.PathLike[str]) -> list[dict[str, str]]:
    """The queries of a CSV file: one dict per row with the keys of :data:`QUERY_COLUMNS` (text as written).

    Parameters
    ----------
    path : str or path
        A UTF-8 CSV file with a header naming at least ``a_start, b_start, a_goal, b_goal`` (spaces around
        names and values are ignored; blank lines are skipped).

    Returns
    -------
    list of dict
        ``{"a_start": ..., "b_start": ..., "a_goal": ..., "b_goal": ...}`` per row; a missing cell is ``""``
        (that row's result is then ``bad input``).

    Raises
    ------
    InvalidInputError
        The file is missing, unreadable, not UTF-8 text, empty, or its header lacks a column.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InvalidInputError(f"--queries is {str(path)!r}, which does not exist, expected a CSV file") from None
    except IsADirectoryError:
        raise InvalidInputError(f"--queries is {str(path)!r}, which is a directory, expected a CSV file") from None
    except UnicodeDecodeError:
        raise InvalidInputError(f"--queries {str(path)!r} is not UTF-8 text, expected a CSV file") from None
    except OSError as exc:
        raise InvalidInputError(f"--queries {str(path)!r} cannot be read: {exc.strerror or exc}") from None
    reader = csv.reader(io.StringIO(text))
    rows = [r for r in reader if any(c.strip() for c in r)]
    if not rows:
        raise InvalidInputError(
            f"--queries {str(path)!r} is empty, expected a header {','.join(QUERY_COLUMNS)} and one row per query"
        )
    header = [c.strip() for c in rows[0]]
    missing = [c for c in QUERY_COLUMNS if c not in header]
    if missing:
        raise InvalidInputError(
            f"--queries {str(path)!r} has the columns {header}, expected {', '.join(QUERY_COLUMNS)} "
            f"(missing {', '.join(missing)})"
        )
    where = [header.index(c) for c in QUERY_COLUMNS]
    return [{c: (r[i].strip() if i < len(r) else "") for c, i in zip(QUERY_COLUMNS, where)} for r in rows[1:]]


def _route_text(route: Sequence[dict[str, Any]]) -> str:
    return " ".join(f"{piece['edge']}{'+' if int(piece['dir']) > 0 else '-'}" for piece in route)


def _generator(layout: dict[str, Any], config: dict[str, Any]) -> Any:
    """The worker's :class:`TrajectoryGenerator` for ``layout`` and ``config`` (built on first use)."""
    import json

    from trajopt.generator import TrajectoryGenerator
    from trajopt.timing import Limits

    key = (json.dumps(layout, sort_keys=True), json.dumps(config, sort_keys=True))
    gen = _GENERATORS.get(key)
    if gen is None:
        track = GraphTrack.from_layout(layout)
        limits = Limits(config["vmax"], config["amax"], config["jmax"])
        gen = TrajectoryGenerator(
            track,
            clearance=config["clearance"],
            limits=limits,
            rate=config["rate"],
            footprint=config.get("footprint"),
        )
        _GENERATORS.clear()  # one configuration per batch: keep only the current one
        _GENERATORS[key] = gen
    return gen


def run_query(
    layout: dict[str, Any], config: dict[str, Any], row: int, query: dict[str, str], setpoints: bool
) -> tuple[dict[str, Any], str | None]:
    """Plan, time and verify one query; never raises for a bad or unsolvable query.

    Parameters
    ----------
    layout : dict
        The layout (:meth:`GraphTrack.to_dict`), shipped to the worker.
    config : dict
        ``clearance`` (m), ``vmax`` (m/s), ``amax`` (m/s²), ``jmax`` (m/s³), ``rate`` (Hz).
    row : int
        The query's number (0 for the first row of the file).
    query : dict
        ``a_start, b_start, a_goal, b_goal`` as written in the file.
    setpoints : bool
        Also return the setpoints CSV text of an ``ok`` query.

    Returns
    -------
    record : dict
        The result row (keys :data:`RESULT_COLUMNS`).
    csv_text : str or None
        The verified setpoints (``mpa trajectory --graph``'s ``setpoints.csv``), with ``setpoints`` and ``ok``.
    """
    from trajopt import plan_kernel

    plan_kernel.install()  # the compiled graph search, in every worker (loaded from the cache the batch warmed)
    rec: dict[str, Any] = {c: "" for c in RESULT_COLUMNS}
    rec.update(query)
    rec["row"] = row
    text: str | None = None
    t0 = time.perf_counter()
    try:
        gen = _generator(layout, config)
        track = gen.track
        start = tuple(track.position(query[f"{r}_start"], f"{r}_start of row {row}") for r in "ab")
        goal = tuple(track.position(query[f"{r}_goal"], f"{r}_goal of row {row}") for r in "ab")
        t0 = time.perf_counter()
        traj = gen.generate(start, goal)
        rec["compute_time"] = time.perf_counter() - t0
        routes = traj.routes()
        rec.update(
            status="ok",
            makespan=float(traj.makespan),
            min_separation=float(traj.min_separation),
            route_a=_route_text(routes["a"]),
            route_b=_route_text(routes["b"]),
        )
        if setpoints:
            text = traj.csv_text()
    except NoMotionError as exc:
        rec.update(status="no motion", message=_one_line(exc), compute_time=time.perf_counter() - t0)
    except InvalidInputError as exc:
        rec.update(status="bad input", message=_one_line(exc), compute_time=time.perf_counter() - t0)
    except MPAError as exc:
        rec.update(status="internal error", message=_one_line(exc), compute_time=time.perf_counter() - t0)
    except Exception as exc:  # a bug in one query must not stop the others
        rec.update(
            status="internal error",
            message=_one_line(f"{type(exc).__name__}: {exc}"),
            compute_time=time.perf_counter() - t0,
        )
    return rec, text


def _one_line(exc: object) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


class _Bar:
    """A progress bar on stderr: tqdm when installed, else one rewritten line; silent when disabled."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.done, self.enabled = total, 0, enabled
        self._tqdm: Any = None
        if enabled:
            try:
                from tqdm import tqdm

                self._tqdm = tqdm(total=total, desc="mpa batch", unit="query", file=sys.stderr, dynamic_ncols=True)
            except ImportError:
                self._tqdm = None

    def update(self) -> None:
        self.done += 1
        if self._tqdm is not None:
            self._tqdm.update()
        elif self.enabled:
            print(f"\rmpa batch {self.done}/{self.total}", end="", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self._tqdm is not None:
            self._tqdm.close()
        elif self.enabled:
            print(file=sys.stderr)


def _value(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.9g}"
    return str(v)


def results_csv_text(records: Iterable[dict[str, Any]]) -> str:
    """The text of ``results.csv``: a header of :data:`RESULT_COLUMNS`, one row per record, in row order."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(RESULT_COLUMNS)
    for rec in sorted(records, key=lambda r: int(r["row"])):
        w.writerow([_value(rec.get(c, "")) for c in RESULT_COLUMNS])
    return buf.getvalue()


def _run_local(
    jobs: list[tuple[int, dict[str, str]]],
    layout: dict[str, Any],
    config: dict[str, Any],
    setpoints: bool,
    workers: int,
    done: Callable[[dict[str, Any], str | None], None],
) -> None:
    if workers <= 1:
        for row, q in jobs:
            done(*run_query(layout, config, row, q, setpoints))
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    ctx = multiprocessing.get_context("spawn")  # fresh interpreters: no forked CasADi/numba state
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
        futures = [pool.submit(run_query, layout, config, row, q, setpoints) for row, q in jobs]
        for f in as_completed(futures):
            done(*f.result())


def _run_dask(
    jobs: list[tuple[int, dict[str, str]]],
    layout: dict[str, Any],
    config: dict[str, Any],
    setpoints: bool,
    address: str,
    done: Callable[[dict[str, Any], str | None], None],
) -> None:
    try:
        from dask.distributed import Client
        from dask.distributed import as_completed as dask_completed
    except ImportError:
        raise InvalidInputError(
            "--dask needs the optional dependency dask.distributed, which is not installed: "
            "pip install 'lollipop-mpa[dask]'"
        ) from None
    try:
        client = Client(address, timeout=DASK_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InvalidInputError(
            f"--dask is {address!r}, which cannot be reached ({_one_line(exc)}), "
            "expected the address of a running Dask scheduler (tcp://HOST:PORT)"
        ) from None
    with client:
        n = len(jobs)
        futures = client.map(
            run_query,
            [layout] * n,
            [config] * n,
            [row for row, _ in jobs],
            [q for _, q in jobs],
            [setpoints] * n,
            pure=False,
        )
        for f in dask_completed(futures):
            done(*f.result())


def run_batch(
    track: GraphTrack,
    queries: Sequence[dict[str, str]],
    out: str | os.PathLike[str],
    *,
    clearance: float = TRAJECTORY_DEFAULTS["clearance"],
    vmax: float = TRAJECTORY_DEFAULTS["vmax"],
    amax: float = TRAJECTORY_DEFAULTS["amax"],
    jmax: float = TRAJECTORY_DEFAULTS["jmax"],
    rate: float = TRAJECTORY_DEFAULTS["rate"],
    footprint: str | None = None,
    setpoints: bool = False,
    workers: int | None = None,
    dask_address: str | None = None,
    progress: bool = False,
) -> list[dict[str, Any]]:
    """Run every query on ``track`` and write ``out/results.csv`` (and ``out/<row>/setpoints.csv``).

    Parameters
    ----------
    track : GraphTrack
        The layout.
    queries : sequence of dict
        As :func:`read_queries` returns them.
    out : str or path
        Output directory (created if needed).
    clearance, vmax, amax, jmax, rate : float
        As ``mpa trajectory``: m, m/s, m/s², m/s³, Hz.
    footprint : str, optional
        ``--footprint``: the robots' bodies in the plane (a spec as :func:`mpa.footprint.parse_footprint` reads).
    setpoints : bool
        Write each ``ok`` query's setpoints to ``out/<row>/setpoints.csv``.
    workers : int, optional
        Local processes (1: this process); default ``os.cpu_count()``, at most ``len(queries)``.
    dask_address : str, optional
        Address of a running Dask scheduler; the queries run on its workers (``workers`` is then ignored).
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    list of dict
        The result rows (keys :data:`RESULT_COLUMNS`), in row order.

    Raises
    ------
    InvalidInputError
        ``workers`` below 1, an unreachable Dask scheduler, an output that cannot be written.
    """
    from trajopt.cli.trajectory import write_outputs
    from trajopt.export import atomic_write_text

    if workers is not None and workers < 1:
        raise InvalidInputError(f"--workers is {workers}, expected a number of processes >= 1")
    config = {
        "clearance": float(clearance),
        "vmax": vmax,
        "amax": amax,
        "jmax": jmax,
        "rate": rate,
        "footprint": footprint,
    }
    _generator(track.to_dict(), config)  # bad clearance, limits or rate: one error before any work
    from trajopt import plan_kernel

    if plan_kernel.install():  # compiled (or loaded from the cache) once here, before the workers load it
        plan_kernel.warm()
    layout = track.to_dict()
    jobs = list(enumerate(queries))
    d = Path(out)
    created = not d.exists()
    d.mkdir(parents=True, exist_ok=True)
    records: list[dict[str, Any]] = []
    bar = _Bar(len(jobs), progress)

    def done(rec: dict[str, Any], text: str | None) -> None:
        if text is not None:
            write_outputs(d / str(rec["row"]), {SETPOINTS_FILE: text})
        records.append(rec)
        bar.update()

    try:
        try:
            if dask_address:
                _run_dask(jobs, layout, config, setpoints, dask_address, done)
            else:
                n = min(workers or os.cpu_count() or 1, max(len(jobs), 1))
                _run_local(jobs, layout, config, setpoints, n, done)
        finally:
            bar.close()
        try:
            atomic_write_text(d / RESULTS_FILE, results_csv_text(records))
        except OSError as exc:
            raise output_error("--out", d / RESULTS_FILE, exc) from None
    except BaseException:  # the batch itself failed (or was interrupted): leave nothing of this run behind
        for rec in records:
            shutil.rmtree(d / str(rec["row"]), ignore_errors=True)
        if created:
            shutil.rmtree(d, ignore_errors=True)
        raise
    return sorted(records, key=lambda r: int(r["row"]))


def _cmd_batch(args: argparse.Namespace) -> int:
    validate_output_dir(args.out)
    track = graph_from_args(args)
    queries = read_queries(args.queries)
    progress = not args.no_progress and sys.stderr.isatty()
    records = run_batch(
        track,
        queries,
        args.out,
        **trajectory_options(args),
        footprint=args.footprint,
        setpoints=args.setpoints,
        workers=args.workers,
        dask_address=args.dask,
        progress=progress,
    )
    counts = {s: sum(r["status"] == s for r in records) for s in STATUSES}
    print(f"queries     {len(records)}: " + ", ".join(f"{n} {s}" for s, n in counts.items()))
    print(f"wrote       {Path(args.out) / RESULTS_FILE}")
    return 0


def register(subparsers: Any) -> None:
    """Add ``batch`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = subparsers.add_parser("batch", help="plan and verify every query of a CSV file on a layout (local or Dask)")
    p.add_argument("--graph", metavar="FILE", required=True, help="the track layout (JSON, or an Open-RMF map)")
    add_map_arguments(p)
    p.add_argument(
        "--queries",
        metavar="QUERIES.csv",
        required=True,
        help="CSV with columns a_start,b_start,a_goal,b_goal (positions EDGE:OFFSET or vertex names)",
    )
    p.add_argument("--out", metavar="DIR", required=True, help="output directory (results.csv, <row>/setpoints.csv)")
    add_clearance_argument(p)
    add_footprint_argument(p)
    d = TRAJECTORY_DEFAULTS
    p.add_argument("--vmax", type=float, default=d["vmax"], help=f"speed limit per robot, m/s (default {d['vmax']:g})")
    p.add_argument("--amax", type=float, default=d["amax"], help=f"acceleration limit, m/s^2 (default {d['amax']:g})")
    p.add_argument("--jmax", type=float, default=d["jmax"], help=f"jerk limit, m/s^3 (default {d['jmax']:g})")
    p.add_argument("--rate", type=float, default=d["rate"], help=f"setpoint rate in Hz (default {d['rate']:g})")
    p.add_argument(
        "--dask", metavar="ADDRESS", default=None, help="run on the Dask cluster at ADDRESS (tcp://HOST:PORT)"
    )
    p.add_argument(
        "--workers", type=int, default=None, metavar="N", help="local processes (default: the number of cores)"
    )
    p.add_argument("--setpoints", action="store_true", help="also write DIR/<row>/setpoints.csv for every ok query")
    p.add_argument("--no-progress", action="store_true", help="no progress bar (default: one on a terminal)")
    p.set_defaults(func=_cmd_batch)
