"""The lazy command registry of ``imil`` (issue 16, goal 1 "Start-up").

``imil --help`` lists every command from ``cli.main.COMMANDS`` without importing the command
modules; each command is imported when it runs.  The table's short help must say what the
command's own docstring says, so the listing cannot drift from the commands.
"""

from __future__ import annotations

import subprocess
import sys

import pytest
import typer

from impedance_mil.cli.main import COMMANDS, app, load_target

try:
    from typer._click.utils import make_default_short_help
except ImportError:  # pragma: no cover - depends on the installed typer
    from click.utils import make_default_short_help  # type: ignore[no-redef]

#: Modules a command that only reads a configuration must not import (issue 16: python-control
#: 1.9 s, matplotlib, numba kernels, dask, pandas/pyarrow).
HEAVY = ("control", "matplotlib", "numba", "dask", "distributed", "pandas", "pyarrow")

#: Prints the heavy modules and the command modules imported by ``imil ARGS``, after it ran.
PROBE = """
import atexit, sys
def report():
    print(" ".join(sorted(m for m in sys.modules if m.split(".")[0] in {heavy!r}
                          or m.startswith("impedance_mil.cli.") and m != "impedance_mil.cli.main")))
atexit.register(report)
from impedance_mil.cli.main import run
sys.argv = ["imil", *sys.argv[1:]]
run()
"""


def imported_by(*args: str) -> set[str]:
    """The heavy modules and command modules a fresh ``imil ARGS`` imports."""
    done = subprocess.run(
        [sys.executable, "-c", PROBE.format(heavy=set(HEAVY)), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    return set(done.stdout.splitlines()[-1].split())  # the probe's line comes last


def test_help_imports_no_command_module_and_nothing_heavy():
    assert imported_by("--help") == set()


@pytest.mark.parametrize("argv", [("table", "info"), ("vs", "list"), ("lab", "show")], ids=" ".join)
def test_configuration_commands_import_nothing_heavy(argv):
    modules = imported_by(*argv)
    assert not {m for m in modules if m.split(".")[0] in HEAVY}, modules


def test_help_lists_every_command_in_the_table_order(imil, tmp_path):
    result = imil("--help", cwd=tmp_path)
    listed = [line.split()[0] for line in result.stdout.split("Commands:")[1].splitlines() if line.strip()]
    assert listed == list(COMMANDS)


@pytest.mark.parametrize("name", list(COMMANDS))
def test_table_help_is_the_commands_own_first_sentence(name):
    command = typer.main.get_command(app).commands[name]
    for limit in (45, 80, 10_000):  # the width of a terminal, and no truncation
        assert make_default_short_help(COMMANDS[name].help, limit) == command.get_short_help_str(limit)


def test_every_target_exists():
    for entry in COMMANDS.values():
        assert callable(load_target(entry.target)) or isinstance(load_target(entry.target), typer.Typer)
