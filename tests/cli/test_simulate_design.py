"""`imil simulate --design` and `imil track --design`: a design file run as it was designed.

Invariant: a run of a design file is the run of the design it holds.  The
report's SD2 design at 80 Hz written with `imil design -o` and run with
`--design` gives the metrics of `imil simulate --vs SD2` to the last bit (the
file's round trip and the discretization are exact; the run designs the same
controller itself).  The refusals are one line naming the option, exit 2,
nothing written.
"""

import json
import sys

import pytest

from impedance_mil.cli.main import run
from impedance_mil.design import load_design
from impedance_mil.implement.export import controller_from_design
from impedance_mil.lab.choices import Choices, mil_test
from impedance_mil.lab.experiments import _runtime

from .test_simulate_cli import imil

SHORT = ["--duration", "2"]
METRICS = ("nrms_error", "peak_error", "spectral_error_0p25_15hz", "spectral_error_15_50hz", "energy_error")


@pytest.fixture(scope="module")
def design_files(tmp_path_factory):
    """SD2 standardized and tracking designs at 80 Hz on the report's table, written by `imil design -o`."""
    folder = tmp_path_factory.mktemp("designs")
    mp = pytest.MonkeyPatch()
    files = {}
    for name, args in {"sd2": ["--vs", "SD2"], "tracking": ["--form", "tracking"]}.items():
        files[name] = folder / f"{name}.json"
        mp.setattr(sys, "argv", ["imil", "design", *args, "--fc", "80", "-o", str(files[name])])
        with pytest.raises(SystemExit) as exc:
            run()
        assert exc.value.code == 0
    mp.undo()
    return files


def test_a_design_file_runs_bit_for_bit_as_the_run_that_designs_it(
    design_files, tmp_path, monkeypatch, capsys
):
    common = [*SHORT, "--json", "--overwrite"]
    rc0, out0, _ = imil(monkeypatch, capsys, "simulate", "--vs", "SD2", "-o", tmp_path / "a.h5", *common)
    rc1, out1, _ = imil(
        monkeypatch, capsys, "simulate", "--design", design_files["sd2"], "-o", tmp_path / "b.h5", *common
    )
    assert rc0 == rc1
    a, b = json.loads(out0), json.loads(out1)
    assert [a[k] for k in METRICS] == [b[k] for k in METRICS]
    assert b["vs"] == "SD2" and b["fc_hz"] == 80.0
    assert b["design_file"] == str(design_files["sd2"]) and b["design_method"] == "filter"
    assert a["design_file"] is None and "fc" not in "".join(b["from_report"])  # the cut-off is the file's
    # the designed VS is not a preset fitted to the report's article: nothing of the VS from the report
    assert "specimen.article_weight" in a["from_report"] and "specimen.article_weight" not in b["from_report"]
    assert "vs.preset" not in b["from_report"]


def test_the_run_executes_the_exported_controller(design_files):
    # one discretization for both: the run's runtime holds export's DiscreteController, section by section
    test = mil_test(Choices(design=design_files["sd2"]))
    design = load_design(design_files["sd2"])
    runtime = _runtime(test.table, test.design, test.vs, "double", None)
    exported = controller_from_design(design)
    for ran, written in zip(runtime.controller.channels, exported.channels, strict=True):
        assert ran.name == written.name
        assert (ran.system_matrix() == written.system_matrix()).all()  # exactly, not to a tolerance


def test_track_runs_a_tracking_design(design_files, tmp_path, monkeypatch, capsys):
    rc, out, _ = imil(
        monkeypatch,
        capsys,
        "track",
        "--design",
        design_files["tracking"],
        "-o",
        tmp_path / "t.h5",
        *SHORT,
        "--json",
    )
    assert rc == 0 and json.loads(out)["design_file"] == str(design_files["tracking"])


@pytest.mark.parametrize(
    ("command", "design", "extra", "message"),
    [
        ("simulate", "sd2", ["--fc", "90"], "--fc: expected no cut-off with --design"),
        ("simulate", "tracking", [], "--design: expected a design of the standardized form"),
        ("track", "sd2", [], "--design: expected a design of the tracking form"),
        ("simulate", "sd2", ["--set", "Ke=4"], "--design: the design was made for another table (Ke = 5"),
        (
            "simulate",
            "sd2",
            ["--set", "loop_time=0.001"],
            "--design: expected a design for the run's loop time",
        ),
        ("simulate", "sd2", ["--set-vs", "T_vs=3"], "--set-vs: expected no VS values with --design"),
        ("simulate", "sd2", ["--vs", "LR2"], "--vs: expected the VS of --design, SD2"),
    ],
)
def test_refusals_name_the_option_and_write_nothing(
    design_files, tmp_path, monkeypatch, capsys, command, design, extra, message
):
    out = tmp_path / "run.h5"
    rc, _, err = imil(
        monkeypatch, capsys, command, "--design", design_files[design], *extra, "-o", out, *SHORT
    )
    assert rc == 2 and message in err and "Traceback" not in err
    assert not out.exists()


def test_another_table_runs_with_force_and_says_so(design_files, tmp_path, monkeypatch, capsys):
    args = ["--design", design_files["sd2"], "--set", "Ke=4.5", "--force", "-o", tmp_path / "f.h5", *SHORT]
    rc, _, err = imil(monkeypatch, capsys, "simulate", *args)
    assert rc == 0 and "Ke = 5 in the design, 4.5 in the run" in err and "running anyway (--force)" in err
