"""`imil report RUN.h5 -o run.html` and `--report`: self-contained run pages; one-line errors."""

import base64
import re
import sys

import h5py
import numpy as np
import pytest

from impedance_mil.cli.main import run
from impedance_mil.cli.runopts import read_summary
from impedance_mil.lab import load_run, run_tracking, save_run
from impedance_mil.lab.metrics import evaluate_run
from impedance_mil.plant import TableParameters
from impedance_mil.report.html import fmt_number
from impedance_mil.signals import builtin_motion
from impedance_mil.specimens import FluidVessel


def imil(*args):
    """Run ``imil ARGS`` in-process; return the exit status (output goes to pytest's capture)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(sys, "argv", ["imil", *map(str, args)])
        with pytest.raises(SystemExit) as exc:
            run()
    return exc.value.code


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """A completed MIL run (0.4 g, 5 s) and the default one, which the stroke interlock stops."""
    folder = tmp_path_factory.mktemp("runs")
    ok, tripped = folder / "ok.h5", folder / "tripped.h5"
    assert imil("simulate", "--pga", "0.4", "--duration", "5", "-o", ok, "--report", folder / "ok.html") == 0
    assert imil("simulate", "--duration", "4", "-o", tripped) == 3
    return folder, ok, tripped


def images(page: str) -> list[bytes]:
    return [base64.b64decode(data) for data in re.findall(r'src="data:image/png;base64,([^"]+)"', page)]


def assert_self_contained(page: str) -> None:
    assert page.startswith("<!DOCTYPE html>") and "<script" not in page
    assert not re.search(r'(src|href)="(?!data:)', page)  # nothing fetched: only data: URIs


def test_report_of_a_mil_run(runs, capsys):
    folder, ok, _ = runs
    out = folder / "page.html"
    assert imil("report", ok, "-o", out) == 0
    assert capsys.readouterr().out.strip() == f"wrote {out}"
    page = out.read_text()
    assert_self_contained(page)
    pngs = images(page)
    assert len(pngs) == 3 and all(p.startswith(b"\x89PNG\r\n\x1a\n") and len(p) > 10_000 for p in pngs)
    for heading in (
        "Status",
        "Metrics",
        "Histories",
        "Response spectra",
        "Force-displacement",
        "Configuration",
    ):
        assert f"<h2>{heading}</h2>" in page
    assert "<p>completed;" in page
    summary, _ = read_summary(ok)
    assert fmt_number(summary["spectral_error_0p25_15hz"]) in page
    # --report on simulate drew the same figures from the in-memory run (the file is lossless).
    assert images((folder / "ok.html").read_text()) == pngs


def test_stored_vs_model_loop_is_the_spring_damper_force(runs):
    # Section 5.3 (Eq 5-1): the SD isolator force is k_s u + c u' along the VS states (u, u').
    _, ok, _ = runs
    result = load_run(ok)
    _, arrays = read_summary(ok)
    loop = arrays["vs_model_loop"]
    vs = result.config["vs"]
    u, v = result.vs_states[:, 0], result.vs_states[:, 1]
    np.testing.assert_allclose(loop["displacement_in"], u, rtol=0, atol=0)
    np.testing.assert_allclose(
        loop["force_lbf"],
        vs["k_s"] * u + vs["c"] * v,
        rtol=1e-9,
        atol=1e-9 * np.max(np.abs(loop["force_lbf"])),
    )


def test_report_of_a_tripped_run_states_the_limit(runs):
    folder, _, tripped = runs
    out = folder / "tripped.html"
    assert imil("report", tripped, "-o", out) == 0
    page = out.read_text()
    trip = load_run(tripped).trip
    assert f"stopped: limit &#x27;stroke&#x27; tripped at t = {trip.time_s:.4f} s" in page
    assert "abort_reason" in page and len(images(page)) == 3


def test_report_of_a_run_file_without_summary_recomputes_metrics(tmp_path):
    # A run file written by the library (as a campaign does): metrics from lab.metrics.evaluate_run.
    gm = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.4).trimmed(0.0, 4.0)
    result = run_tracking(TableParameters.report_default(), gm, specimen=FluidVessel(water_depth_in=18.0))
    path = save_run(result.run, tmp_path / "lab.h5")
    out = tmp_path / "lab.html"
    assert imil("report", path, "-o", out) == 0
    page = out.read_text()
    assert fmt_number(evaluate_run(load_run(path)).spectral_error_low) in page
    assert len(images(page)) == 2  # tracking: no isolator loop


@pytest.mark.parametrize("case", ["missing", "not hdf5", "not a run", "exists", "same file"])
def test_report_bad_input_one_line_exit_2(runs, tmp_path, capsys, case):
    _, ok, _ = runs
    source, out = ok, tmp_path / "page.html"
    if case == "missing":
        source = tmp_path / "none.h5"
    elif case == "not hdf5":
        source = tmp_path / "text.h5"
        source.write_text("not an HDF5 file")
    elif case == "not a run":
        source = tmp_path / "other.h5"
        with h5py.File(source, "w") as fh:
            fh["x"] = [1.0]
    elif case == "exists":
        out.write_text("keep")
    else:
        out = ok
    before = sorted(p.name for p in tmp_path.iterdir())
    capsys.readouterr()
    assert imil("report", source, "-o", out) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("imil: error:")
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    if case == "exists":
        assert out.read_text() == "keep"
