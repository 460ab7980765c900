"""Entry point of the ``imil`` command.

Every command group lives in its own module and is listed here, in
:data:`COMMANDS`, by name: ``imil --help`` lists the commands from that
table without importing them, and a command's module is imported only when
the command runs (or its own help is asked for), so that ``imil table info``
does not pay for python-control, matplotlib, numba or dask
(docs/architecture.md, "The lazy command registry").  The error contract is
kept here, for every command: the library raises
:class:`~impedance_mil.errors.ImilError` subclasses, click refuses unknown
options and malformed values; :func:`run` turns each (and bad file paths)
into one line on stderr, ``imil: error: ...``, and exit status 2, never a
traceback.  ``tests/cli/test_error_contract.py`` walks this app and checks
every command.
"""

from __future__ import annotations

import importlib
import sys
import warnings
from collections.abc import Iterator, Mapping, MutableMapping
from types import MappingProxyType
from typing import Any, NamedTuple

import typer
from typer.core import TyperGroup
from typer.main import get_command_from_info, get_group_from_info
from typer.models import CommandInfo, TyperInfo

from ..errors import ImilError
from ..plausibility import one_line_warning

# typer >= 0.20 parses with its own copy of click (typer._click); older versions with click itself.
try:
    from typer._click import Command, Context, HelpFormatter
    from typer._click import exceptions as usage
    from typer._click.utils import make_default_short_help
except ImportError:  # pragma: no cover - depends on the installed typer
    from click import Command, Context, HelpFormatter  # type: ignore[assignment]
    from click import exceptions as usage  # type: ignore[no-redef]
    from click.utils import make_default_short_help  # type: ignore[no-redef]

#: ``imil`` or a command group without a command: click prints the help (click >= 8.2).
_NO_ARGS_HELP = getattr(usage, "NoArgsIsHelpError", ())


class LazyCommand(NamedTuple):
    """A command of ``imil`` before its module is imported."""

    #: ``"module:attribute"``: a :class:`typer.Typer` (a command group) or a command function.
    target: str
    #: The first sentence of its help, as ``imil --help`` lists it (held equal to the
    #: command's own docstring by tests/cli/test_lazy_registry.py).
    help: str


#: Every command of ``imil``, in the order ``imil --help`` lists them.
COMMANDS: MappingProxyType[str, LazyCommand] = MappingProxyType(
    {
        "demo": LazyCommand(
            "impedance_mil.cli.demo:demo",
            "The report's default configuration end to end: table model, MIL controller, "
            "virtual test, HTML report.",
        ),
        "design": LazyCommand(
            "impedance_mil.cli.design_cmd:design",
            "Design the impedance-matching MIL controller and check constraints I, II, III.",
        ),
        "export": LazyCommand(
            "impedance_mil.cli.export:export",
            "Export a discretized MIL controller as C, IEC 61131-3 ST, JSON or CSV.",
        ),
        "simulate": LazyCommand(
            "impedance_mil.cli.simulate:simulate",
            "MIL run: the table imitates a virtual isolation system under a ground motion (Section 9).",
        ),
        "track": LazyCommand(
            "impedance_mil.cli.simulate:track",
            "Acceleration tracking: the table reproduces the ground motion under the specimen (Section 8).",
        ),
        "frf": LazyCommand(
            "impedance_mil.cli.simulate:frf",
            "Multisine test of the table (Section 4.5): FRFs, identified omega_oil, zeta_oil, d, model error.",
        ),
        "report": LazyCommand(
            "impedance_mil.cli.report_cmd:report",
            "Write the self-contained HTML report of one run (in --units us|si).",
        ),
        "identify": LazyCommand(
            "impedance_mil.cli.identify:identify",
            "Identify the table (physical and rational models, with confidence intervals) from a recording.",
        ),
        "evaluate": LazyCommand(
            "impedance_mil.cli.evaluate:evaluate",
            "Judge a recorded tracking or MIL test with the metrics, run file and page of a virtual run.",
        ),
        "table": LazyCommand(
            "impedance_mil.cli.table:app",
            "Shake-table model: parameters, poles, transfer functions, tuning.",
        ),
        "vs": LazyCommand(
            "impedance_mil.cli.vs:app",
            "Virtual isolation systems: presets, properties, force-displacement loops.",
        ),
        "motion": LazyCommand(
            "impedance_mil.cli.motion:app",
            "Ground motions: info, response spectrum, table feasibility check.",
        ),
        "campaign": LazyCommand(
            "impedance_mil.cli.campaign:app",
            "Parameter sweeps (campaigns) and the report-reproduction suite.",
        ),
        "drive": LazyCommand(
            "impedance_mil.cli.drive:app",
            "Drive files for the lab's controller (multisine, ground motion).",
        ),
        "recording": LazyCommand(
            "impedance_mil.cli.recording:app",
            "Recordings: write a virtual run as the lab's recording.",
        ),
        "lab": LazyCommand(
            "impedance_mil.cli.labcmd:app",
            "Laboratory setup: table, interlocks, sensors, controller, specimen.",
        ),
    }
)


def load_target(target: str) -> Any:
    """The object ``"module:attribute"`` names, importing its module.

    This is the registry's one import by name, on demand (:mod:`importlib`): the design that
    keeps ``imil --help`` light, not a function-local import dodging a cycle.
    """
    module_name, _, attribute = target.partition(":")
    return getattr(importlib.import_module(module_name), attribute)


class LoadedCommands(MutableMapping[str, Command]):
    """A group's commands by name; a :class:`LazyCommand` becomes a click command on first access.

    Listing the names (``list``, ``in``, ``len``) imports nothing; reading a command imports
    its module, once.
    """

    def __init__(self, entries: dict[str, LazyCommand | Command], group: LazyGroup) -> None:
        self._entries = entries
        self._group = group

    def pending(self, name: str) -> LazyCommand | None:
        """The table entry of ``name`` if its module is not loaded yet, else None."""
        entry = self._entries.get(name)
        return entry if isinstance(entry, LazyCommand) else None

    def __getitem__(self, name: str) -> Command:
        entry = self._entries[name]
        if isinstance(entry, LazyCommand):
            entry = self._entries[name] = self._group.build(name, load_target(entry.target))
        return entry

    def __setitem__(self, name: str, command: Command) -> None:
        self._entries[name] = command

    def __delitem__(self, name: str) -> None:
        del self._entries[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)


class LazyGroup(TyperGroup):
    """The ``imil`` group: its commands come from :data:`COMMANDS`, imported when first used.

    ``list_commands`` and ``imil --help`` read only the table; ``get_command`` (running a
    command, its ``--help``, or a walk over ``commands.items()`` as the tests do) imports the
    command's module and builds it with this group's settings, as ``add_typer`` and
    ``command`` would have.  Commands added eagerly (``add_typer``, ``@app.command()``)
    take precedence, in the table's place.

    A command group whose heavy commands live in another module names its own table in a
    subclass (``cli/table.py``: ``imil table bode`` and ``rlocus`` are in
    ``cli/table_figures.py``, which imports matplotlib), and passes it as its Typer's ``cls``.
    """

    #: The group's commands by name, in the order its help lists them.
    registry: Mapping[str, LazyCommand] = COMMANDS

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        self.commands = LoadedCommands({**self.registry, **self.commands}, self)

    def build(self, name: str, target: Any) -> Command:
        """The click command of ``target``: a :class:`typer.Typer` (a group) or a function."""
        if isinstance(target, typer.Typer):
            return get_group_from_info(
                TyperInfo(target, name=name),
                pretty_exceptions_short=app.pretty_exceptions_short,
                rich_markup_mode=self.rich_markup_mode,
                suggest_commands=self.suggest_commands,
            )
        return get_command_from_info(
            CommandInfo(name=name, callback=target),
            pretty_exceptions_short=app.pretty_exceptions_short,
            rich_markup_mode=self.rich_markup_mode,
        )

    def list_commands(self, ctx: Context) -> list[str]:
        """The names of the commands, in the table's order, without importing them."""
        return list(self.commands)

    def format_commands(self, ctx: Context, formatter: HelpFormatter) -> None:
        """The "Commands" section: short help from the table for commands not loaded yet."""
        names = self.list_commands(ctx)
        limit = formatter.width - 6 - max((len(name) for name in names), default=0)
        rows = []
        for name in names:
            pending = self.commands.pending(name) if isinstance(self.commands, LoadedCommands) else None
            if pending is not None:
                rows.append((name, make_default_short_help(pending.help, limit)))
                continue
            command = self.get_command(ctx, name)
            if command is not None and not command.hidden:
                rows.append((name, command.get_short_help_str(limit)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


def _imil() -> None:
    """The group itself takes no options (a Typer app without commands needs a callback)."""


app = typer.Typer(
    name="imil",
    cls=LazyGroup,
    callback=_imil,
    help="impedance-mil: impedance-matching control for shake-table testing and MIL simulation.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Help texts hold units in brackets ([in], [lbf], [g]): Rich markup would eat them.
    rich_markup_mode=None,
)

#: Exit status for bad input (configuration, data files, usage).
EXIT_BAD_INPUT = 2


#: Exit status after Ctrl-C outside a run (like a shell after SIGINT).
EXIT_INTERRUPTED = 130


def _error(text: str) -> None:
    """One line on stderr and exit status 2."""
    print("imil: error: " + " ".join(str(text).split()), file=sys.stderr)
    sys.exit(EXIT_BAD_INPUT)


def run() -> None:
    """Run ``imil`` on ``sys.argv`` and exit.

    Usage errors (an unknown option, a malformed value, a missing argument),
    errors the library raises on purpose, and unreadable or unwritable paths
    become one line on stderr with exit status 2; ``imil`` or a command group
    without a command prints its help (exit status 2, as click does).
    """
    warnings.formatwarning = one_line_warning  # the package's warnings as one line on stderr
    try:
        code = app(standalone_mode=False)
    except _NO_ARGS_HELP as exc:
        exc.show()
        sys.exit(exc.exit_code)
    except usage.UsageError as exc:
        command = exc.ctx.command_path if exc.ctx is not None else "imil"
        _error(f"{command}: {exc.format_message()}")
    except usage.ClickException as exc:
        _error(exc.format_message())
    except typer.Abort:
        print("imil: interrupted", file=sys.stderr)
        sys.exit(EXIT_INTERRUPTED)
    except ImilError as exc:
        _error(str(exc))
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        _error(f"{where}{exc.strerror or exc}")
    sys.exit(code if isinstance(code, int) else 0)


if __name__ == "__main__":  # pragma: no cover
    run()
