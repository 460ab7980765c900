"""The error contract of every ``imil`` command (issue 11, item 6): bad input gets one line and exit 2.

The test walks the typer app, so a command or subcommand added later is covered without
editing this file.  Each command runs in-process (the ``imil`` fixture of tests/conftest.py,
which calls ``cli.main.run`` as the console script does) in an empty folder, twice:

* with an unknown option;
* with a bad value, chosen from the command's own parameters: its required arguments get a
  path under a regular file (no preset, record, campaign, kind or file has that name);
  without a required argument, its first numeric option gets ``not-a-number``; without a
  numeric option, its first option taking a value gets that path; a command whose parameters
  are all flags gets that path as an argument it does not take
  (``test_commands_without_values_are_the_known_ones`` lists them).  Other required options
  get the same path.

Each run must exit with status 2, print exactly one line on stderr starting ``imil: error:``
(without "Traceback"), and leave the folder empty.
"""

from __future__ import annotations

import typing
from pathlib import Path

import pytest
import typer

from impedance_mil.cli.main import EXIT_BAD_INPUT, app

#: A path whose parent is a regular file: nothing can be read from or written to it.
BAD_PATH = str(Path(__file__).resolve() / "not-a-folder")
#: A value no numeric option accepts.
NOT_A_NUMBER = "not-a-number"
#: Commands whose parameters are all flags (checked, so that a new value-less command is noticed).
WITHOUT_VALUES = {("campaign", "list"), ("motion", "list")}


def _commands(command, path=()):
    subcommands = getattr(command, "commands", None)
    if subcommands:
        for name, sub in sorted(subcommands.items()):
            yield from _commands(sub, (*path, name))
    else:
        yield path, command


COMMANDS = dict(_commands(typer.main.get_command(app)))


def _takes_value(param) -> bool:
    return not getattr(param, "is_flag", False) and not getattr(param, "hidden", False)


def _is_numeric(command, param) -> bool:
    hint = typing.get_type_hints(command.callback).get(param.name)
    return any(t in (int, float) for t in typing.get_args(hint) or (hint,))


def _flag(param) -> str:
    return max(param.opts, key=len)


def takes_no_value(command) -> bool:
    """Whether every parameter of ``command`` is a flag."""
    return not any(_takes_value(p) for p in command.params)


def bad_value_argv(path: tuple[str, ...], command) -> list[str] | None:
    """The arguments of a run of ``command`` with one bad value (None: it takes no value)."""
    if takes_no_value(command):
        return None
    params = [p for p in command.params if _takes_value(p)]
    arguments = [p for p in params if p.param_type_name == "argument" and p.required]
    options = [p for p in params if p.param_type_name == "option"]
    argv = [*path, *(BAD_PATH for _ in arguments)]
    if not arguments:
        numeric = [p for p in options if _is_numeric(command, p)]
        chosen = (numeric or options)[0]
        argv += [_flag(chosen), NOT_A_NUMBER if numeric else BAD_PATH]
        options = [p for p in options if p is not chosen]
    for p in options:
        if p.required:
            argv += [_flag(p), BAD_PATH]
    return argv


def assert_refused(result, folder: Path, *names: str) -> None:
    lines = result.stderr.strip().splitlines()
    assert result.returncode == EXIT_BAD_INPUT, result.stderr
    assert len(lines) == 1 and lines[0].startswith("imil: error:"), result.stderr
    assert "Traceback" not in result.stderr + result.stdout
    assert all(name in lines[0] for name in names), lines[0]
    assert list(folder.iterdir()) == []  # nothing written


def test_the_walk_finds_every_command():
    # The commands of README/docs; the walk must find at least these (new ones are welcome).
    expected = {
        ("campaign", "run"),
        ("demo",),
        ("design",),
        ("export",),
        ("frf",),
        ("motion", "check"),
        ("report",),
        ("simulate",),
        ("table", "tune"),
        ("track",),
        ("vs", "loops"),
    }
    assert expected <= set(COMMANDS) and len(COMMANDS) >= 25


@pytest.mark.parametrize("path", sorted(COMMANDS), ids=" ".join)
def test_unknown_option_is_one_line_exit_2(imil, tmp_path, path):
    assert_refused(imil(*path, "--no-such-option", cwd=tmp_path), tmp_path, "--no-such-option")


@pytest.mark.parametrize("path", sorted(COMMANDS), ids=" ".join)
def test_bad_value_is_one_line_exit_2(imil, tmp_path, path):
    argv = bad_value_argv(path, COMMANDS[path])
    if argv is None:  # only flags: an argument it does not take is its bad value
        argv = [*path, BAD_PATH]
    named = [argv[argv.index(NOT_A_NUMBER) - 1]] if NOT_A_NUMBER in argv else []
    assert_refused(imil(*argv, cwd=tmp_path), tmp_path, *named)


def test_commands_without_values_are_the_known_ones():
    assert {p for p, c in COMMANDS.items() if takes_no_value(c)} == WITHOUT_VALUES


def test_vs_specific_form_of_a_linear_vs_is_refused_naming_the_option(imil, tmp_path):
    # SD2 is linear (no f_h, report Section 6.2): the vs-specific form has no H_ufh to build.
    # This ended in a traceback with exit status 1 before.
    result = imil("design", "--vs", "SD2", "--form", "vs-specific", "-o", "d.json", cwd=tmp_path)
    assert_refused(result, tmp_path, "--form", "vs-specific", "SD")
