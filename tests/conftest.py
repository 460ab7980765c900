"""Shared fixtures: the ``imil`` command run in-process, as the console script runs it."""

from __future__ import annotations

import sys
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
