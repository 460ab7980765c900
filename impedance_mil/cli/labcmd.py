"""`imil lab`: the laboratory setup (lab file) a run uses: show it, check it.

``imil lab show [--lab FILE|report] [--table FILE] [--json]`` prints the
effective setup with units and where each value came from (``file``,
``default``, ``--set``); ``imil lab check FILE`` validates a lab file and
names the section and key of the first problem (exit 2).
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..config import parse_overrides
from ..display import human_name
from ..lab.labfile import load_lab
from ..report.documents import express
from .common import UnitsOpt, console, output_units, print_json

app = typer.Typer(
    help="Laboratory setup: table, interlocks, sensors, controller, specimen.", no_args_is_help=True
)


def _say(text: str) -> None:
    console.print(text, markup=False)


@app.command()
def show(
    lab: str | None = typer.Option(None, "--lab", help="Lab file or 'report' (default)."),
    table: Path | None = typer.Option(None, "--table", help="A bare table file (a lab with only a table)."),
    sets: list[str] | None = typer.Option(None, "--set", help="Table value KEY=VALUE (repeatable)."),
    json: bool = typer.Option(False, "--json", help="Print JSON."),
    units: str | None = UnitsOpt,
) -> None:
    """The effective setup, with units and the source of each value."""
    shown = output_units(units, lab, table)
    setup = load_lab(
        lab if lab is not None or table is not None else "report",
        table=table,
        overrides=parse_overrides(sets),
    )
    doc = setup.to_dict()
    if json:
        print_json(doc, shown)
        return
    sources = doc["sources"]
    view = express(doc, shown)
    unit_of = view["units"]
    _say(f"lab {doc['lab']} ({doc['file']}); printed in {shown.value} units")
    _say(f"  table: {sources.get('table', 'file')}; loop time {setup.table.loop_time * 1e6:g} us")
    for section in ("limits", "controller", "specimen"):
        _say(f"[{section}]")
        for key, value in view[section].items():
            unit = human_name(unit_of.get(f"{section}.{key}", ""))
            text = "none" if value is None else (f"{value:.6g}" if isinstance(value, float) else str(value))
            tail = f" {unit}" if unit not in ("", "1") and value is not None else ""
            _say(f"  {key:22s} {text}{tail}   ({sources.get(f'{section}.{key}', 'derived')})")
    for key, rng in (view["uncertainty"] or {}).items():
        end = "" if "min" in rng else "_loops"
        unit = human_name(unit_of.get(f"uncertainty.{key}.min{end}", ""))
        tail = f" {unit}" if unit not in ("", "1") else ""
        _say(
            f"[uncertainty] {key:18s} {rng['min' + end]:.6g} to {rng['max' + end]:.6g}{tail} "
            f"(nominal {rng['nominal' + end]:.6g})"
        )
    for part, values in view["dynamics"].items():
        if not isinstance(values, dict):  # a table dynamic: 0 or None is off
            if values:
                unit = human_name(unit_of.get(f"dynamics.{part}", ""))
                _say(f"[dynamics] {part:22s} {values:.6g} {unit}")
            continue
        _say(f"[dynamics.{part}]")
        for key, value in values.items():
            unit = human_name(unit_of.get(f"dynamics.{part}.{key}", ""))
            text = "none" if value is None else (f"{value:.6g}" if isinstance(value, float) else str(value))
            tail = f" {unit}" if unit not in ("", "1") and value is not None else ""
            _say(f"  {key:22s} {text}{tail}")
    _say(f"[sensors] clipping {doc['sensors']['clipping']} ({sources['sensors']})")
    for ch in view["sensors"]["channels"]:
        low, high = ch["range"]
        _say(
            f"  {ch['name']:14s} {ch['quantity']:22s} {low:.6g} to {high:.6g} {ch['unit']}, "
            f"step {ch['resolution']:.3g}, noise {ch['noise_rms']:.3g} rms, share {ch['share']:g}"
            + (
                ""
                if ch.get("bandwidth") is None
                else f", anti-alias {ch['bandwidth']:g} Hz (order {ch['filter_order']})"
            )
            + ("" if ch.get("delay_s") is None else f", delay {ch['delay_s'] * 1e3:g} ms")
            + ("" if ch.get("noise_spectrum") is None else f", {ch['noise_spectrum']['kind']} noise spectrum")
        )


@app.command()
def check(lab: str = typer.Argument(..., help="Lab file (TOML) or 'report'.")) -> None:
    """Validate a lab file: every section and key, one line per problem found (exit 2)."""
    setup = load_lab(lab)
    defaults = ", ".join(setup.defaults) or "none"
    _say(f"{setup.name}: ok; generic defaults used for: {defaults}")
