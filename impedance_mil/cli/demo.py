"""`imil demo`: the main job on the built-in default (for now: the table model of Section 4)."""

from __future__ import annotations

from pathlib import Path

import typer

from ..plant import LinearTable, TableParameters
from ..report import table_plots
from ..systems import pole_table
from .common import console


def _say(text: str) -> None:
    console.print(text, markup=False)


def demo(out: Path = typer.Option(Path("demo-output"), "--out", help="Output folder.")) -> None:
    """Model summary of the report's shake table (Table 4.1) with Bode and root-locus plots."""
    out.mkdir(parents=True, exist_ok=True)
    p = TableParameters.report_default()
    _say("Shake table of the report (Table 4.1, d = 1e5 per docs/errata.md), internal units:")
    for key, value in p.to_dict().items():
        _say(f"  {key:22s} {value}")
    for delay in ("none", "first-order", "sampled"):
        tbl = LinearTable(p, delay=delay)
        _say(f"closed-loop poles, delay model '{delay}' "
             f"(stable: {'yes' if tbl.is_stable() else 'NO'}):")
        for row in pole_table(tbl.poles()):
            _say(f"  {row['frequency_hz']:9.2f} Hz  zeta {row['damping']:7.3f}  "
                 f"({row['real']:.1f} {row['imag']:+.1f}j rad/s)")
    written = [table_plots.save_bode(p, out / "table_bode.png")]
    for name in ("Ke", "Kp", "loop_time"):
        written.append(table_plots.save_root_locus(p, name, out / f"table_rlocus_{name}.png"))
    for path in written:
        _say(f"wrote {path}")
