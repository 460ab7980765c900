"""Entry point of the ``imil`` command.

Every command group lives in its own module and is registered here.  The
error contract is kept here, for every command: the library raises
:class:`~impedance_mil.errors.ImilError` subclasses, click refuses unknown
options and malformed values; :func:`run` turns each (and bad file paths)
into one line on stderr, ``imil: error: ...``, and exit status 2, never a
traceback.  ``tests/cli/test_error_contract.py`` walks this app and checks
every command.
"""

from __future__ import annotations

import sys
import warnings

import typer

from ..errors import ImilError
from ..plausibility import one_line_warning
from . import (
    campaign,
    demo,
    design_cmd,
    drive,
    evaluate,
    export,
    identify,
    labcmd,
    motion,
    recording,
    report_cmd,
    simulate,
    table,
    vs,
)

# typer >= 0.20 parses with its own copy of click (typer._click); older versions with click itself.
try:
    from typer._click import exceptions as usage
except ImportError:  # pragma: no cover - depends on the installed typer
    from click import exceptions as usage  # type: ignore[no-redef]

#: ``imil`` or a command group without a command: click prints the help (click >= 8.2).
_NO_ARGS_HELP = getattr(usage, "NoArgsIsHelpError", ())

app = typer.Typer(
    name="imil",
    help="impedance-mil: impedance-matching control for shake-table testing and MIL simulation.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Help texts hold units in brackets ([in], [lbf], [g]): Rich markup would eat them.
    rich_markup_mode=None,
)
app.add_typer(table.app, name="table")
app.add_typer(vs.app, name="vs")
app.add_typer(motion.app, name="motion")
app.command("demo")(demo.demo)
app.command("design")(design_cmd.design)
app.command("export")(export.export)
app.command("simulate")(simulate.simulate)
app.command("track")(simulate.track)
app.command("frf")(simulate.frf)
app.command("report")(report_cmd.report)
app.add_typer(campaign.app, name="campaign")
app.add_typer(drive.app, name="drive")
app.command("identify")(identify.identify)
app.command("evaluate")(evaluate.evaluate)
app.add_typer(recording.app, name="recording")
app.add_typer(labcmd.app, name="lab")

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
