"""Spreading the queries: in process, over a local process pool, or over an existing Dask cluster.

Each task is one query with its configuration (:func:`bench.runner.run_query`); a worker builds its objects
once per configuration and keeps them (:func:`bench.runner.context`). Results come back as plain records and
are sorted by track, query and method, so the output does not depend on the order in which tasks finish.

- ``workers == 1`` and no cluster: in this process.
- ``workers > 1``: :class:`concurrent.futures.ProcessPoolExecutor` with the ``spawn`` start method (OMPL, CasADi
  and toppra are imported fresh in every worker, never forked with their state).
- ``dask_address``: ``dask.distributed.Client(address)`` (the optional ``dask`` extra). The ``bench`` package is
  shipped to the workers with ``Client.upload_file``; ``mpa``, ``trajopt`` and the ``bench`` extra (ompl)
  must be installed there. A worker process runs one query at a time (a process-wide lock) so that compute
  times are not inflated by threads sharing the interpreter and OMPL's process-wide seeding stays
  deterministic: start workers with ``--nthreads 1`` and as many processes as cores.
"""

from __future__ import annotations

import multiprocessing
import os
import tempfile
import zipfile
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from bench.runner import METHODS, run_query

__all__ = ["run_tasks", "sort_records"]

Task = tuple[dict[str, Any], dict[str, Any]]


def sort_records(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Records in a reproducible order (sweep, scale, grid, track, query, method)."""
    return sorted(
        records,
        key=lambda r: (
            str(r.get("sweep", "")),
            float(r.get("scale", 0.0)),
            -float(r.get("grid_h", 0.0)),
            r["track"],
            r["query"],
            METHODS.index(r["method"]),
        ),
    )


def _progress(total: int, enabled: bool, desc: str) -> Any:
    from tqdm import tqdm

    return tqdm(total=total, disable=not enabled, desc=desc, unit="query", dynamic_ncols=True)


def _tagged(task: Task, recs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    tags = task[1].get("tags", {})
    return [{**r, **tags} for r in recs]


def run_tasks(
    tasks: Sequence[Task],
    *,
    workers: int | None = None,
    dask_address: str | None = None,
    progress: bool = True,
    desc: str = "benchmark",
) -> list[dict[str, Any]]:
    """Run every task and return all records, sorted (see the module docstring for where they run).

    Parameters
    ----------
    tasks : sequence of (config dict, query dict)
        A query may carry ``tags`` (copied into its records, e.g. the scaling sweep's parameters).
    workers : int, optional
        Local worker processes; default ``os.cpu_count()``.
    dask_address : str, optional
        Scheduler address of an existing Dask cluster (``tcp://host:8786``); overrides ``workers``.
    progress : bool
        Show a tqdm progress bar.
    """
    records: list[dict[str, Any]] = []
    bar = _progress(len(tasks), progress, desc)
    try:
        if dask_address:
            records = _run_dask(tasks, dask_address, bar)
        else:
            n = workers or os.cpu_count() or 1
            if n <= 1:
                for t in tasks:
                    records.extend(_tagged(t, run_query(*t)))
                    bar.update()
            else:
                ctx = multiprocessing.get_context("spawn")
                with ProcessPoolExecutor(max_workers=n, mp_context=ctx) as pool:
                    futs = {pool.submit(run_query, *t): t for t in tasks}
                    for f in as_completed(futs):
                        records.extend(_tagged(futs[f], f.result()))
                        bar.update()
    finally:
        bar.close()
    return sort_records(records)


def _package_zip(directory: str) -> str:
    """Zip the ``bench`` package into ``directory`` (for ``Client.upload_file``)."""
    pkg = Path(__file__).resolve().parent
    path = os.path.join(directory, "bench.zip")
    with zipfile.ZipFile(path, "w") as zf:
        for f in sorted(pkg.glob("*.py")):
            zf.write(f, f"bench/{f.name}")
    return path


def _run_dask(tasks: Sequence[Task], address: str, bar: Any) -> list[dict[str, Any]]:
    try:
        from dask.distributed import Client
        from dask.distributed import as_completed as dask_completed
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise SystemExit(f"error: --dask needs the optional extra: pip install 'dask[distributed]' ({exc})") from exc
    records: list[dict[str, Any]] = []
    with Client(address) as client, tempfile.TemporaryDirectory() as tmp:
        client.upload_file(_package_zip(tmp))
        futs = client.map(run_query, [t[0] for t in tasks], [t[1] for t in tasks], pure=False)
        index = {f.key: t for f, t in zip(futs, tasks)}
        for f in dask_completed(futs):
            records.extend(_tagged(index[f.key], f.result()))
            bar.update()
    return records
