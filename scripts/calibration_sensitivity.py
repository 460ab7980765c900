"""Which added dynamic can move the calibrating observation? (issue 17, item 2: evidence).

Runs ONLY the calibrating observation of ``impedance_mil/data/calibration/footnote22.toml``
(tracking, 42 in of water, GM1, f_c = 100 and 150 Hz: the report found 100 Hz stable and
150 Hz unstable) on the report's lab with one added dynamic at a time, over the range its
cited source gives (docs/lab.md Section 1.1, docs/specimens.md "Sensor dynamics"), and prints
each run's verdict by the claims' rule and its hf_ratio (rms above 15 Hz over the target's;
unstable above 1).  No predicted claim is run.  The last rows add a delay the controller's
design does not know (``[uncertainty] extra_delay``'s meaning, in whole loops): the size of
unmodelled command-path lag the observation needs.

    python scripts/calibration_sensitivity.py          # about 30 runs, a few seconds each
"""

from __future__ import annotations

import copy
import tempfile
from dataclasses import replace
from pathlib import Path

from impedance_mil.campaign import labkinds
from impedance_mil.campaign.claims import run_stability
from impedance_mil.campaign.kinds import get_kind
from impedance_mil.campaign.params import set_path

TABLE = Path(labkinds.__file__).parents[1] / "data" / "tables" / "report_table_4_1.toml"
BASE = f"""
[table]
file = "{TABLE.as_posix()}"
[limits]
stroke = "3 in"
velocity = "40 in/s"
[sensors]
preset = "table-7.1"
clipping = "warn"
[controller]
precision = "single"
feedback = "lc"
substeps = "auto"
"""
LOAD_CELLS = ("LC-03", "LC-06", "LC-08", "LC-14")
ALL_CHANNELS = ("accelerometer", "string_pot", "dp_cell", *LOAD_CELLS)


def _delay(ms: float, names: tuple[str, ...]) -> str:
    return "".join(f'[sensors.{n}]\ndelay = "{ms} ms"\n' for n in names)


#: (dynamic, value shown, lab-file text added to BASE), over each source's range.
CASES = [
    ("none (report's lab)", "-", ""),
    *[("load-cell conditioner delay", f"{x} ms", _delay(x, LOAD_CELLS)) for x in (0.2, 0.4, 0.6)],
    *[("converter delay, every channel", f"{x} ms", _delay(x, ALL_CHANNELS)) for x in (0.2, 0.4, 0.6)],
    *[
        ("spool rate limit", f"full stroke {x} ms", f'[dynamics.valve]\nfull_stroke_time = "{x} ms"\n')
        for x in (4, 7, 10)
    ],
    (
        "seal friction with pressure",
        "0.00155 + 0.05 lbf/psi",
        '[dynamics.friction]\npressure_coefficient = "0.00155 lbf/psi"\nload_pressure_coefficient = "0.05 lbf/psi"\n',
    ),
    *[
        (
            "load cells (shear), 100 lb plate",
            f"{k:.0e} lbf/in",
            f'[dynamics.load_cells]\nstiffness = "{k} lbf/in"\ndamping = "2 %"\nbase_mass = "100 lb"\n',
        )
        for k in (2e7, 2e6, 2e5)
    ],
    *[
        (
            "platen mode, 10 % of m_st",
            f"{f} Hz",
            f'[dynamics.platen]\nmass_fraction = "10 %"\nfrequency = "{f} Hz"\n',
        )
        for f in (300, 150, 100)
    ],
    *[
        ("compliant mount", f"{k:.1e} lbf/in", f'[dynamics.foundation]\nstiffness = "{k} lbf/in"\n')
        for k in (1.3e6, 5e5)
    ],
]


def run_case(lab_text: str | None, fc: float, folder: Path, extra_loops: int = 0) -> tuple[str, float]:
    """Verdict and hf_ratio of the observation's tracking run at ``fc`` [Hz] on the lab ``lab_text``."""
    kind = get_kind("tracking")
    config = copy.deepcopy(dict(kind.defaults))
    for name, value in {"water_depth": 42.0, "motion": "GM1", "f_c": fc}.items():
        set_path(config, kind.params[name].path, value)
    if lab_text is not None:
        lab = folder / f"lab-{abs(hash(lab_text))}.toml"
        lab.write_text(lab_text)
        set_path(config, "lab", str(lab))
    config = kind.resolve(config) if kind.resolve else config
    if extra_loops:
        # a delay the design does not know: the lab's output delay beyond the table's (as [uncertainty] extra_delay)
        test, source = labkinds.tracking_test_of(config)
        test = replace(test, lab=replace(test.lab, output_delay=test.lab.output_delay + extra_loops))
        metrics = labkinds.controlled_metrics(test, test.run(), source, folder / "run.h5")
    else:
        metrics = kind.run(config, folder / "run.h5")
    row = {**metrics, "status": "aborted" if metrics.get("aborted") else "ok"}
    return run_stability(row) or "inconclusive", float(metrics.get("hf_ratio") or 0.0)


def main() -> None:
    print("observation: tracking, 42 in, GM1; report: f_c = 100 Hz stable, 150 Hz unstable")
    print(f"{'dynamic':34s} {'value':24s} {'f_c = 100 Hz':>22s} {'f_c = 150 Hz':>22s}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        rows = [(name, value, BASE + text, 0) for name, value, text in CASES]
        rows += [("unmodelled command delay", f"+{n} loop(s)", BASE, n) for n in (1, 2)]
        for name, value, text, extra in rows:
            cells = [run_case(text, fc, folder, extra) for fc in (100.0, 150.0)]
            shown = [f"{v} ({hf:.3f})" for v, hf in cells]
            print(f"{name:34s} {value:24s} {shown[0]:>22s} {shown[1]:>22s}", flush=True)


if __name__ == "__main__":
    main()
