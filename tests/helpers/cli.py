"""Running the ``mpa`` command line in the test's process: its exit status and what it printed."""

from __future__ import annotations

import contextlib
import io

import pytest

from trajopt.cli import main


def run_main(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    """``mpa ARGV`` run by :func:`trajopt.cli.main`, its output read from pytest's ``capsys``.

    Returns
    -------
    (int, str, str)
        The exit status, stdout and stderr.
    """
    rc = main(argv)
    out, err = capsys.readouterr()
    return rc, out, err


def run_redirected(argv: list[str]) -> tuple[int, str, str]:
    """``mpa ARGV`` run by :func:`trajopt.cli.main` with stdout and stderr redirected to strings (no fixture
    needed, e.g. inside a hypothesis test or a thread).

    Returns
    -------
    (int, str, str)
        The exit status, stdout and stderr.
    """
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()
