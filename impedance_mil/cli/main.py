"""Entry point of the ``imil`` command.

Every command group lives in its own module and is registered here.  The
library raises :class:`~impedance_mil.errors.ImilError` subclasses; this
module turns them (and bad file paths) into one line on stderr and exit
status 2, never a traceback.
"""

from __future__ import annotations

import sys

import typer

from ..errors import ImilError
from . import campaign, demo, design_cmd, export, motion, report_cmd, simulate, table, vs

app = typer.Typer(
    name="imil",
    help="impedance-mil: impedance-matching control for shake-table testing and MIL simulation.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
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

#: Exit status for bad input (configuration, data files, usage).
EXIT_BAD_INPUT = 2


def run() -> None:
    """Run ``imil`` on ``sys.argv`` and exit.

    Usage errors are reported by typer itself (exit status 2); errors the
    library raises on purpose, and unreadable or unwritable paths, become
    one line on stderr with exit status 2.
    """
    try:
        app()
    except ImilError as exc:
        print(f"imil: error: {exc}", file=sys.stderr)
        sys.exit(EXIT_BAD_INPUT)
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"imil: error: {where}{exc.strerror or exc}", file=sys.stderr)
        sys.exit(EXIT_BAD_INPUT)


if __name__ == "__main__":  # pragma: no cover
    run()
