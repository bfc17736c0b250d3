"""The compiled kernels see one argument type each, whatever the caller passes (ints, other tracks, other rates).

A call with another argument type (an int where a float was compiled, a non-contiguous array, int32 edges)
would compile another specialization at run time (about a second, in the middle of a query). The pipeline
converts every argument to the one type; this checks it on a varied workload, in a fresh process (other tests
call the kernels directly with arguments of their own).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from trajopt._numba import HAVE_NUMBA

ROOT = Path(__file__).resolve().parents[2]

WORKLOAD = """
import json
import numpy as np
from mpa import Circle, GraphTrack, Interval, Lollipop, MPAError
from trajopt import Limits, TrajectoryGenerator
from trajopt.verify import kernels as gate_kernels
from trajopt.verify import sampling as sample_kernels
from trajopt.verify.gate import between_rows_separation

rng = np.random.default_rng(4)
done = 0
for track in (Lollipop(1, 1), Lollipop(0.3, 1.2), Circle(1), Lollipop(1.0, 2), Interval(2)):
    for lim, rate in ((Limits(), 100), (Limits((0.5, 1), 2, 10), 250.0)):
        gen = TrajectoryGenerator(track, clearance=0.05, limits=lim, rate=rate)
        for _ in range(6):
            try:
                traj = gen.generate(rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2))
            except MPAError:
                continue
            traj.at_rate(1000)
            between_rows_separation(track, traj.plan.routes, traj.s[::3], traj.a[::3], 0.03, lim)
            done += 1
graph = GraphTrack.from_json("examples/tracks/warehouse.json")
gen = TrajectoryGenerator(graph, clearance=0.1)
names = graph.graph.vertices
for k in range(4):
    try:
        gen.generate((names[k], names[-1 - k]), (names[-2 - k], names[k + 1]))
        done += 1
    except MPAError:
        pass
sigs = {}
for mod in (gate_kernels, sample_kernels):
    for name in mod.__all__:
        f = getattr(mod, name)
        if hasattr(f, "signatures"):
            sigs[name] = [str(s) for s in f.signatures]
print(json.dumps({"done": done, "signatures": sigs}))
"""


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba is not installed: the kernels run as plain Python")
def test_each_kernel_is_compiled_for_one_argument_type() -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    res = subprocess.run([sys.executable, "-c", WORKLOAD], cwd=ROOT, env=env, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout.strip().splitlines()[-1])
    assert out["done"] > 30
    used = {name: s for name, s in out["signatures"].items() if s}
    assert {"check_rows", "sample_rows", "track_positions", "word_samples"} <= set(used)
    for name, s in used.items():
        assert len(s) == 1, (name, s)
        # C-contiguous arrays of float64 / int64 / bool only (another layout or width is another compilation)
        assert "'A'" not in s[0] and "'F'" not in s[0] and "int32" not in s[0] and "float32" not in s[0], (name, s)


@pytest.mark.slow  # compiles every kernel in a fresh process (about 10 s)
@pytest.mark.skipif(not HAVE_NUMBA, reason="numba is not installed: the kernels run as plain Python")
def test_without_a_place_for_numbas_cache_the_kernels_compile_in_memory() -> None:
    # numba refuses cache=True where it finds no writable cache directory (a read-only install); an unknown
    # locator class makes it refuse the same way. The import must not fail and the gate must still run.
    script = (
        "from mpa import Lollipop\n"
        "from trajopt import TrajectoryGenerator, gate_kernels\n"
        "t = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05).generate((0.1, 0.6), (0.3, 0.8))\n"
        "print(t.verification['ok'], type(gate_kernels.check_rows._cache).__name__)\n"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_LOCATOR_CLASSES": "NoSuchLocator"}
    res = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["True", "NullCache"]
