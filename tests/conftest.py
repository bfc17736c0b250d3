"""Fixtures shared by test files of several folders (helpers that are plain functions are in ``tests/helpers``)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import settings

# Property tests draw the same examples on every run (a red CI run can be reproduced, and a green one stays green);
# MPA_HYPOTHESIS_RANDOM=1 draws new ones, as when hunting for counterexamples. A test's own settings still apply.
settings.register_profile("derandomized", derandomize=True, print_blob=True)
settings.register_profile("random", print_blob=True)
settings.load_profile("random" if os.environ.get("MPA_HYPOTHESIS_RANDOM") == "1" else "derandomized")

# The graph planner's compiled search (trajopt.plan_kernel) plans what the reference search plans, node for node;
# tests/trajopt/test_plan_kernel.py checks it on thousands of queries. Elsewhere (this process and the processes it
# starts: batch workers, subprocesses) the reference searches, so that one test process compiles the kernels (about
# 45 s), not every one.
os.environ["TRAJOPT_SEARCH"] = "python"


@pytest.fixture(scope="session", autouse=True)
def layout_cache_dir(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """The converted maps' cache (:mod:`mpa.openrmf.cache`) in a directory of the session, not the user's."""
    old = os.environ.get("MPA_CACHE_DIR")
    os.environ["MPA_CACHE_DIR"] = str(tmp_path_factory.mktemp("layout-cache"))
    yield
    if old is None:
        os.environ.pop("MPA_CACHE_DIR", None)
    else:
        os.environ["MPA_CACHE_DIR"] = old


@pytest.fixture(scope="module")
def client() -> Any:
    """Starlette's ``TestClient`` of the app of ``mpa serve`` (:func:`trajopt.web.app.create_app`), one per module.

    Starlette is imported here, when a test asks for it: the files that use it skip without the extra ``[serve]``.
    """
    from starlette.testclient import TestClient

    from trajopt.web.app import create_app

    return TestClient(create_app())
