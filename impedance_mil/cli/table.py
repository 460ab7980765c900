"""`imil table`: the shake-table model (report Sections 3-4).

Every command takes ``--table FILE`` (default: the report's Table 4.1, as
corrected in docs/errata.md), repeated ``--set KEY=VALUE`` overrides (bare
numbers in report units, or quantities with units) and ``--json``.

``info``, ``poles``, ``tf`` and ``bode`` also take an LTI table file
(``[model] kind = "transfer-function" | "zpk" | "state-space"``,
:mod:`impedance_mil.plant.lti_table`), with its own delay treatment (``--delay``
and ``--set`` are refused for it); ``rlocus`` and ``tune`` need the physical
parameters and refuse it naming ``--table``.
"""

from __future__ import annotations

from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import typer

from ..display import UnitSystem
from ..errors import ConfigError
from ..lazy import lazy_attributes
from ..plant import TableParameters
from .common import LabOpt, UnitsOpt, console, output_units, print_fields, print_json, table_definition
from .main import LazyCommand, LazyGroup

if TYPE_CHECKING:  # an LTI table is the table definition that is not TableParameters
    from ..plant.lti_table import LTITable

#: The commands of ``imil table``, in the order its help lists them: the figures (``bode``,
#: ``rlocus``) live in ``cli/table_figures.py`` and import matplotlib only when they run, the
#: linear model's (``poles``, ``tf``, ``tune``) in ``cli/table_model.py`` with the LTI core,
#: which ``info`` does not need (docs/architecture.md, "The lazy command registry").
TABLE_COMMANDS: MappingProxyType[str, LazyCommand] = MappingProxyType(
    {
        "info": LazyCommand(
            "impedance_mil.cli.table:info",
            "Parameters and derived quantities, with their units (--units us|si); an LTI table: kind, "
            "poles, DC gains.",
        ),
        "poles": LazyCommand(
            "impedance_mil.cli.table_model:poles",
            "Closed-loop poles: frequency [Hz], damping [-], real/imag [rad/s]; reports instability.",
        ),
        "tf": LazyCommand(
            "impedance_mil.cli.table_model:tf",
            "Transfer function output/input: descending powers of s, monic denominator.",
        ),
        "bode": LazyCommand(
            "impedance_mil.cli.table_figures:bode",
            "Bode plots of the six transfer functions (PNG, magnitudes in --units us|si); an LTI "
            "table's paths.",
        ),
        "rlocus": LazyCommand(
            "impedance_mil.cli.table_figures:rlocus",
            "Root locus of the five poles for a K_e, K_p or loop-time sweep (PNG; poles in rad/s).",
        ),
        "tune": LazyCommand(
            "impedance_mil.cli.table_model:tune",
            "Stability limits, break-away points and the K_p maximizing oil-column damping.",
        ),
    }
)


#: ``impedance_mil.cli.table.bode`` and ``rlocus`` read from ``cli/table_figures.py``, ``poles``,
#: ``tf`` and ``tune`` from ``cli/table_model.py`` (PEP 562): where they were, they still are.
_FIGURES = lazy_attributes(__name__, "impedance_mil.cli.table_figures", ("bode", "rlocus"))
_MODEL_COMMANDS = ("poles", "tf", "tune")
_MODEL = lazy_attributes(__name__, "impedance_mil.cli.table_model", _MODEL_COMMANDS)


def __getattr__(name: str) -> Any:
    """A command of ``cli/table_figures.py`` or ``cli/table_model.py`` (an AttributeError for any other name)."""
    return (_MODEL if name in _MODEL_COMMANDS else _FIGURES)(name)


class TableGroup(LazyGroup):
    """``imil table``: the commands of :data:`TABLE_COMMANDS`, each imported when first used."""

    registry = TABLE_COMMANDS


app = typer.Typer(
    cls=TableGroup,
    help="Shake-table model: parameters, poles, transfer functions, tuning.",
    no_args_is_help=True,
)

TableOpt = typer.Option(None, "--table", help="Table file (TOML with units); default: report Table 4.1.")
SetOpt = typer.Option(None, "--set", help="Override KEY=VALUE (repeatable), e.g. Ke=4 or 'mass=1600 lb'.")
JsonOpt = typer.Option(False, "--json", help="Print JSON.")
DelayOpt = typer.Option(
    None,
    "--delay",
    help="Loop-time delay: none, first-order (default), pade, sampled; an LTI table ([model]) states its own.",
)
PadeOpt = typer.Option(6, "--pade-order", help="Order of the Pade approximation.")


def say(text: str) -> None:
    """Print plain text (no rich markup: units like [rad/s] are kept)."""
    console.print(text, markup=False)


def delay_model(delay: str | None, table: TableParameters | LTITable) -> str:
    """``--delay`` for a physical table (default first-order); an LTI table's own (``--delay`` refused)."""
    if not isinstance(table, TableParameters):  # an LTI table
        if delay is not None:
            raise ConfigError(
                "--delay",
                f"no --delay for an LTI table (its [model] delay = {table.delay!r} states it)",
                delay,
            )
        return table.delay
    return "first-order" if delay is None else delay


def _lti_info(t: LTITable, as_json: bool, shown: UnitSystem) -> None:
    data = t.summary()
    if as_json:
        print_json(data, shown)
        return
    say(f"LTI table: {t.kind}, loop time {t.loop_time * 1e6:g} us, delay: {t.delay}")
    say(
        f"outputs: {', '.join(t.outputs)}   stable: {'yes' if data['stable'] else 'NO'}   "
        f"force path (H_zw): {'yes' if data['force_path'] else 'NONE'}"
    )
    pole_lines(data["poles"])
    say("DC gains (internal units: in, lbf, in/s^2, in/s, psi):")
    for name, value in data["dc_gains"].items():
        say(f"  {name:6s} {value:.6g}")


def pole_lines(rows: list[dict]) -> None:
    say(f"{'pole':5s} {'f [Hz]':>9s} {'zeta':>8s} {'real [rad/s]':>14s} {'imag [rad/s]':>14s}")
    for row in rows:
        say(
            f"{row.get('label', ''):5s} {row['frequency_hz']:9.2f} {row['damping']:8.3f} "
            f"{row['real']:14.2f} {row['imag']:14.2f}"
        )


@app.command()
def info(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    set: list[str] | None = SetOpt,
    json: bool = JsonOpt,
    units: str | None = UnitsOpt,
) -> None:
    """Parameters and derived quantities, with their units (--units us|si); an LTI table: kind, poles, DC gains."""
    p = table_definition(table, set, lab)
    shown = output_units(units, lab, table)
    if not isinstance(p, TableParameters):  # an LTI table
        _lti_info(p, json, shown)
        return
    data = {
        "parameters": p.to_dict(),
        "derived": {
            "omega_oil_rad_s": p.omega_oil,
            "bulk_modulus_psi": p.bulk_modulus,
            "leakage_coefficient_in3_s_psi": p.leakage_coefficient,
            "valve_flow_gain_in3_s_mA": p.valve_flow_gain,
        },
    }
    if json:
        print_json(data, shown)
        return
    print_fields({**data["parameters"], **data["derived"]}, shown)
