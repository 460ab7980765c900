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

import typer

from ..display import UnitSystem
from ..errors import ConfigError
from ..lazy import lazy_attributes
from ..plant import LinearTable, TableParameters
from ..plant.lti_table import LTITable
from ..plant.tuning import pole_summary, tuning_summary
from ..report_config import report_config
from ..systems import pole_table
from .common import (
    LabOpt,
    UnitsOpt,
    console,
    option_errors,
    output_units,
    print_fields,
    print_json,
    table_definition,
    table_parameters,
)
from .main import LazyCommand, LazyGroup

_REPORT = report_config()

#: The commands of ``imil table``, in the order its help lists them: the figures (``bode``,
#: ``rlocus``) live in ``cli/table_figures.py`` and import matplotlib only when they run
#: (docs/architecture.md, "The lazy command registry").
TABLE_COMMANDS: MappingProxyType[str, LazyCommand] = MappingProxyType(
    {
        "info": LazyCommand(
            "impedance_mil.cli.table:info",
            "Parameters and derived quantities, with their units (--units us|si); an LTI table: kind, "
            "poles, DC gains.",
        ),
        "poles": LazyCommand(
            "impedance_mil.cli.table:poles",
            "Closed-loop poles: frequency [Hz], damping [-], real/imag [rad/s]; reports instability.",
        ),
        "tf": LazyCommand(
            "impedance_mil.cli.table:tf",
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
            "impedance_mil.cli.table:tune",
            "Stability limits, break-away points and the K_p maximizing oil-column damping.",
        ),
    }
)


#: ``impedance_mil.cli.table.bode`` and ``rlocus`` read from ``cli/table_figures.py`` (PEP 562).
__getattr__ = lazy_attributes(__name__, "impedance_mil.cli.table_figures", ("bode", "rlocus"))


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


def _say(text: str) -> None:
    """Print plain text (no rich markup: units like [rad/s] are kept)."""
    console.print(text, markup=False)


def delay_model(delay: str | None, table: TableParameters | LTITable) -> str:
    """``--delay`` for a physical table (default first-order); an LTI table's own (``--delay`` refused)."""
    if isinstance(table, LTITable):
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
    _say(f"LTI table: {t.kind}, loop time {t.loop_time * 1e6:g} us, delay: {t.delay}")
    _say(
        f"outputs: {', '.join(t.outputs)}   stable: {'yes' if data['stable'] else 'NO'}   "
        f"force path (H_zw): {'yes' if data['force_path'] else 'NONE'}"
    )
    _pole_lines(data["poles"])
    _say("DC gains (internal units: in, lbf, in/s^2, in/s, psi):")
    for name, value in data["dc_gains"].items():
        _say(f"  {name:6s} {value:.6g}")


def _pole_lines(rows: list[dict]) -> None:
    _say(f"{'pole':5s} {'f [Hz]':>9s} {'zeta':>8s} {'real [rad/s]':>14s} {'imag [rad/s]':>14s}")
    for row in rows:
        _say(
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
    if isinstance(p, LTITable):
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


@app.command()
def poles(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    set: list[str] | None = SetOpt,
    json: bool = JsonOpt,
    delay: str = DelayOpt,
    pade_order: int = PadeOpt,
    units: str | None = UnitsOpt,
) -> None:
    """Closed-loop poles: frequency [Hz], damping [-], real/imag [rad/s]; reports instability."""
    p = table_definition(table, set, lab)
    delay = delay_model(delay, p)
    if isinstance(p, LTITable):
        stable, rows = p.is_stable(), pole_table(p.poles())
    else:
        stable, rows = pole_summary(p, delay, pade_order)
    if json:
        print_json({"poles": rows, "stable": stable, "delay": delay}, output_units(units, lab, table))
        return
    _say(f"delay model: {delay}   stable: {'yes' if stable else 'NO'}")
    _pole_lines(rows)


@app.command()
def tf(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    set: list[str] | None = SetOpt,
    json: bool = JsonOpt,
    delay: str = DelayOpt,
    pade_order: int = PadeOpt,
    input: str = typer.Option("u", "--input", help="u (command [in]) or w (force [lbf])."),
    output: str = typer.Option("z", "--output", help="z [in/s^2], x [in], v [in/s] or dp [psi]."),
    units: str | None = UnitsOpt,
) -> None:
    """Transfer function output/input: descending powers of s, monic denominator.

    The coefficients are in internal units (in, in/s^2, lbf, psi; s in rad/s) whatever --units.

    With ``--delay sampled`` the discrete function in z is printed (with ``dt``).  An LTI
    table's function is of its design model (its [model] delay; "sampled": the first-order lag).
    """
    p = table_definition(table, set, lab)
    delay = delay_model(delay, p)
    with option_errors({"output": "--output", "input": "--input"}):
        if isinstance(p, LTITable):
            data = p.tf(output, input).to_dict()  # continuous: "sampled" designs with the first-order lag
        else:
            tbl = LinearTable(p, delay=delay, pade_order=pade_order)
            H = tbl.sampled().tf(output, input) if delay == "sampled" else tbl.tf(output, input)
            data = H.to_dict()
    if json:
        print_json(data, output_units(units, lab, table))
        return
    var = "z" if delay == "sampled" and not isinstance(p, LTITable) else "s"
    _say(f"H_{output}{input}({var}) = num/den, descending powers of {var}")
    _say(f"num = {data['num']}")
    _say(f"den = {data['den']}")


@app.command()
def tune(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    set: list[str] | None = SetOpt,
    json: bool = JsonOpt,
    units: str | None = UnitsOpt,
) -> None:
    """Stability limits, break-away points and the K_p maximizing oil-column damping.

    The report's figures (Section 4.4) are printed for comparison only when the
    table, after ``--set``, is the report's (Table 4.1), whatever file holds it.
    """
    params = table_parameters(table, set, lab)
    data = tuning_summary(params)
    shown = output_units(units, lab, table)
    if json:
        print_json(data, shown)
        return
    _say(f"stable with these parameters: {'yes' if data['stable'] else 'NO'}")
    print_fields({k: ("none found" if v is None else v) for k, v in data.items() if k != "stable"}, shown, 34)
    if params == TableParameters.report_default():
        t = _REPORT.tuning
        _say(
            f"(report Section 4.4: Ke {t.ke_limit:g} V/in, Kp > {t.kp_limit:g} V/psi, break-away Ke "
            f"{t.breakaway_ke:g} / Kp {t.breakaway_kp:g}; model optimum K_p differs from the printed "
            f"{t.chosen_kp:g}, see docs/errata.md)"
        )
