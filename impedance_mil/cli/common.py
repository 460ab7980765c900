"""Small helpers shared by the CLI commands (printing, JSON output, the table option, number lists)."""

from __future__ import annotations

import json
import math
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer
from rich.console import Console

from .. import plant
from ..config import parse_overrides
from ..display import UnitSystem, human_name, unit_system
from ..errors import ConfigError
from ..fileio import json_safe
from ..lazy import LazyModule
from ..plant.table_kind import is_lti_table_file
from ..report.documents import TF_COEFFICIENTS, express

if TYPE_CHECKING:  # the readers are imported on first use (below): `imil table info` needs none
    from ..lab.labfile import LabSetup
    from ..plant import TableParameters
    from ..plant.table_files import TableDefinition

#: The lab-file reader, imported when a command first reads a lab (issue 16, start-up).
labfile = LazyModule("impedance_mil.lab.labfile")
#: The table-file reader of either kind, imported when a command first reads an LTI table file.
table_files = LazyModule("impedance_mil.plant.table_files")

#: Console for human-readable output (stdout).
console = Console(highlight=False, soft_wrap=True)


def print_json(data: Any, units: UnitSystem = UnitSystem.US) -> None:
    """Print ``data`` (internal units) as JSON in ``units``, with its ``units`` block (NaN, inf: null)."""
    doc = express(data, units) if isinstance(data, Mapping) else data
    print(json.dumps(json_safe(doc), indent=2))


def field_lines(data: Mapping[str, Any], units: UnitSystem, width: int = 32, indent: str = "") -> list[str]:
    """``key  value unit`` lines of a flat document (internal units) in ``units``."""
    shown = express(data, units)
    lines = []
    for key, value in shown.items():
        if key in ("units", "unit_system"):
            continue
        unit = shown["units"].get(key, "")
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        tail = "" if unit in ("", "1", "unknown", TF_COEFFICIENTS) else " " + human_name(unit)
        lines.append(f"{indent}{key:{width}s} {text}{tail}")
    return lines


def print_fields(data: Mapping[str, Any], units: UnitSystem, width: int = 32) -> None:
    """Print :func:`field_lines`."""
    for line in field_lines(data, units, width):
        console.print(line, markup=False)


#: The ``--units`` option of every command.
UnitsOpt = typer.Option(
    None, "--units", help="us | si: units of what is printed (default: the lab file's units, else us)."
)


def output_units(units: str | None, lab: str | None = None, table: Path | None = None) -> UnitSystem:
    """``--units``, else the ``units`` of ``--lab``/``--table`` (a lab file may say ``units = "si"``), else us."""
    if units is not None:
        return unit_system(units)
    if lab is None and table is not None and is_lti_table_file(table):
        return UnitSystem.US  # an LTI table file has no lab keys
    if lab is not None or table is not None:
        return labfile.load_lab(lab, table=table, accept_lti=True).units  # the units only: any table will do
    return UnitSystem.US


@contextmanager
def option_errors(options: Mapping[str, str]) -> Iterator[None]:
    """Re-raise a library :class:`ConfigError` on a key of ``options`` as one naming the option.

    The library names its keys (``form``); the user typed an option (``--form``).
    """
    try:
        yield
    except ConfigError as exc:
        if exc.key not in options:
            raise
        raise ConfigError(options[exc.key], exc.expected, exc.got) from None


def table_definition(
    table: Path | None,
    sets: list[str] | None = None,
    lab: str | None = None,
) -> TableDefinition:
    """``--table`` as either kind of table (an LTI table file gives :class:`LTITable`), else :func:`table_parameters`.

    For the commands that take a linear model of any kind (``imil table poles|tf|info|bode``,
    ``imil design``); ``--set`` is refused for an LTI table, and ``--lab`` with ``--table``.
    """
    if table is not None and lab is None and is_lti_table_file(table):
        return table_files.read_table_file(table, parse_overrides(sets))
    return table_parameters(table, sets, lab)


def table_parameters(
    table: Path | None,
    sets: list[str] | None = None,
    lab: str | None = None,
) -> TableParameters:
    """``--table`` or the table of ``--lab`` (default the report's Table 4.1) with ``--set`` overrides.

    Errors name the key or file; a lab's controller loop time, output delay and valve command
    apply to its table.  An LTI table file is refused naming ``--table`` (the command needs
    the physical parameters; :func:`table_definition` takes either).
    """
    if lab is not None or table is not None:
        return labfile.load_lab(lab, table=table, overrides=parse_overrides(sets)).physical_table()
    return plant.TableParameters.from_toml(table or plant.default_table_path(), parse_overrides(sets))


def lab_setup(table: Path | None, sets: list[str] | None = None, lab: str | None = None) -> LabSetup:
    """The lab of ``--lab`` or ``--table`` (default the report's lab) with ``--set`` table overrides."""
    return labfile.load_lab(lab, table=table, overrides=parse_overrides(sets))


def weight_option(option: str, text: str | None, setup: LabSetup | None) -> float:
    """``--specimen-weight``: a weight [lbf] (a force, a mass, ``0``; a bare number is lbf);
    not given: the article of the lab's ``[specimen]``, or none."""
    if text is not None:
        return 0.0 if text.strip() == "0" else labfile.article_weight(text, option)
    if setup is not None and setup.specimen.article_weight is not None:
        return float(setup.specimen.article_weight)
    return 0.0


#: The ``--specimen-weight`` option of the commands that check a motion against a lab.
WeightOpt = typer.Option(
    None,
    "--specimen-weight",
    help="Test-article weight, e.g. '2000 lbf' or '1000 kg' (bare number: lbf); default the lab's "
    "[specimen] article_weight (none without --lab or --table).",
)


#: The ``--lab`` option of every command that takes a table.
LabOpt = typer.Option(
    None, "--lab", help="Lab file (TOML: table, limits, sensors, controller, specimen) or 'report'."
)


def positive_numbers(
    option: str, text: str, malformed: str, invalid: str, count: int | None = None
) -> list[float]:
    """``"80,100,250"`` -> ``[80.0, 100.0, 250.0]``: comma-separated positive finite numbers.

    Raises
    ------
    ConfigError
        Naming ``option``: ``malformed`` when a part is not a number,
        ``invalid`` when there is none, not ``count``, or one is not positive
        and finite.
    """
    try:
        values = [float(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise ConfigError(option, malformed, text) from None
    if (
        not values
        or (count is not None and len(values) != count)
        or not all(v > 0 and math.isfinite(v) for v in values)
    ):
        raise ConfigError(option, invalid, text)
    return values
