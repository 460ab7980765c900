"""`imil table poles|tf|tune`: the commands of the table's linear model (report Section 4).

They live apart from ``cli/table.py`` (the ``imil table`` group, its options and ``info``)
because they need the LTI core (``plant.linear``, ``plant.lti_table``, ``systems``,
``plant.tuning``), which ``imil table info`` does not: issue 16, start-up.  See
``cli/table.py`` for the options they share.
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..plant import LinearTable, TableParameters
from ..plant.lti_table import LTITable
from ..plant.tuning import pole_summary, tuning_summary
from ..report_config import report_config
from ..systems import pole_table
from .common import (
    LabOpt,
    UnitsOpt,
    option_errors,
    output_units,
    print_fields,
    print_json,
    table_definition,
    table_parameters,
)
from .table import DelayOpt, JsonOpt, PadeOpt, SetOpt, TableOpt, delay_model, pole_lines, say

_REPORT = report_config()


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
    say(f"delay model: {delay}   stable: {'yes' if stable else 'NO'}")
    pole_lines(rows)


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
    say(f"H_{output}{input}({var}) = num/den, descending powers of {var}")
    say(f"num = {data['num']}")
    say(f"den = {data['den']}")


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
    say(f"stable with these parameters: {'yes' if data['stable'] else 'NO'}")
    print_fields({k: ("none found" if v is None else v) for k, v in data.items() if k != "stable"}, shown, 34)
    if params == TableParameters.report_default():
        t = _REPORT.tuning
        say(
            f"(report Section 4.4: Ke {t.ke_limit:g} V/in, Kp > {t.kp_limit:g} V/psi, break-away Ke "
            f"{t.breakaway_ke:g} / Kp {t.breakaway_kp:g}; model optimum K_p differs from the printed "
            f"{t.chosen_kp:g}, see docs/errata.md)"
        )
