"""Fixtures of the tests of :mod:`mpa`."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from mpa.planners import corners as graph_corners
from mpa.planners.graph import query as graph_query


@pytest.fixture(autouse=True)
def reference_search() -> Iterator[None]:
    """The tests of :mod:`mpa` test its own search and corners' programme: a compiled one that :mod:`trajopt`
    installed in this worker process (:func:`trajopt.plan_kernel.install`) is set aside while each runs, and put
    back."""
    installed = graph_query.compiled_search()
    programme = graph_corners.compiled_programme()
    graph_query.use_search(None)
    graph_corners.use_programme(None)
    yield
    graph_query.use_search(installed)
    graph_corners.use_programme(programme)
