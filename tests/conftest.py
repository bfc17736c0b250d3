"""Fixtures shared by test files of several folders (helpers that are plain functions are in ``tests/helpers``)."""

from __future__ import annotations

from typing import Any

import pytest


@pytest.fixture(scope="module")
def client() -> Any:
    """Starlette's ``TestClient`` of the app of ``mpa serve`` (:func:`trajopt.web.app.create_app`), one per module.

    Starlette is imported here, when a test asks for it: the files that use it skip without the extra ``[serve]``.
    """
    from starlette.testclient import TestClient

    from trajopt.web.app import create_app

    return TestClient(create_app())
