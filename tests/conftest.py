"""Shared fixtures: the ``imil`` command run in-process, as the console script runs it."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from impedance_mil.cli.main import run


@pytest.fixture
def imil(capfd, monkeypatch):
    """``imil(*args, cwd=DIR)`` runs ``imil ARGS`` in this process.

    Returns ``SimpleNamespace(returncode, stdout, stderr)``; ``cwd`` (default: the
    current folder) is where relative paths resolve.
    """

    def call(*args, cwd=None):
        if cwd is not None:
            monkeypatch.chdir(cwd)
        monkeypatch.setattr(sys, "argv", ["imil", *map(str, args)])
        code = 0
        try:
            run()
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        out, err = capfd.readouterr()
        return SimpleNamespace(returncode=code, stdout=out, stderr=err)

    return call


#: The repository's example of a user-defined VS type (a user's own file, not part of the package).
TWO_STOREY_FILE = Path(__file__).resolve().parent.parent / "examples" / "vs_types" / "two_storey.py"


@pytest.fixture(scope="session")
def two_storey():
    """The example user type file ``examples/vs_types/two_storey.py``, loaded as a module."""
    spec = importlib.util.spec_from_file_location("two_storey_example", TWO_STOREY_FILE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
