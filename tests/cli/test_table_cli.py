"""`imil table ...` and `imil demo`: contracts, units at the edge, one-line errors."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from impedance_mil.cli.main import app
from impedance_mil.plant import LinearTable, TableParameters, default_table_path
from impedance_mil.plant.lti_table import LTITable
from impedance_mil.plant.table_files import lti_table_toml

IMIL = Path(sys.executable).parent / "imil"
runner = CliRunner()


def _json(args):
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_poles_json_contract():
    data = _json(["table", "poles", "--json", "--delay", "none"])
    rows = data["poles"]
    assert len(rows) == 5 and data["stable"] is True
    for row in rows:
        assert {"frequency_hz", "damping", "real", "imag"} <= set(row)
    # Table 4.3, K_p = 0.001, tau = 0: oil column 55 Hz, zeta 0.26 (+-1 Hz, +-0.01).
    oil = [r for r in rows if r["label"] == "p4"][0]
    assert oil["frequency_hz"] == pytest.approx(55, abs=1) and oil["damping"] == pytest.approx(0.26, abs=0.01)
    key = lambda q: (round(q.real, 6), q.imag)  # noqa: E731
    got = sorted((complex(r["real"], r["imag"]) for r in rows), key=key)
    ref = sorted(LinearTable(TableParameters.report_default(), delay="none").poles(), key=key)
    np.testing.assert_allclose(np.array(got, complex), np.array(ref, complex), rtol=1e-12)


def test_tf_json_contract_and_set_with_units():
    data = _json(["table", "tf", "--input", "u", "--output", "x", "--json", "--set", "Ke=0.2 V/mm"])
    assert data["den"][0] == 1.0
    H = LinearTable(TableParameters.report_default().replace(Ke=0.2 * 25.4)).tf("x", "u")
    np.testing.assert_allclose(data["num"], H.num, rtol=1e-12)
    np.testing.assert_allclose(data["den"], H.den, rtol=1e-12)
    dw = _json(["table", "tf", "--input", "w", "--output", "dp", "--json"])
    assert dw["num"][-1] < 0  # the table resists the test-article force
    sampled = _json(["table", "tf", "--delay", "sampled", "--json"])
    assert sampled["variable"] == "z" and sampled["dt"] == pytest.approx(500e-6)


def test_unstable_is_reported_not_an_error():
    data = _json(["table", "poles", "--json", "--set", "Ke=8", "--set", "Kp=0", "--delay", "none"])
    assert data["stable"] is False


def test_info_table_file_and_tune(tmp_path):
    f = tmp_path / "t.toml"
    f.write_text(default_table_path().read_text().replace('mass = "4.14 lbf*s**2/in"', 'mass = "1600 lb"'))
    info = _json(["table", "info", "--table", str(f), "--json"])
    assert info["parameters"]["mass"] == pytest.approx(4.144, abs=0.001)
    tune = _json(["table", "tune", "--json", "--set", "loop_time=0"])
    assert tune["Ke_limit_analog_Kp0"] == pytest.approx(6.7, abs=0.05)  # Section 4.4.2
    assert tune["Kp_breakaway_analog"] == pytest.approx(0.0006, abs=0.00005)  # Section 4.4.3
    assert tune["Kp_limit"] == pytest.approx(0.0039, abs=0.00005)  # errata (0.0035)


def test_plots_are_written(tmp_path):
    res = runner.invoke(app, ["table", "bode", "-o", str(tmp_path / "b.png")])
    assert res.exit_code == 0, res.output
    res = runner.invoke(
        app, ["table", "rlocus", "--param", "Ke", "--max", "10", "-o", str(tmp_path / "r.png")]
    )
    assert res.exit_code == 0, res.output
    for name in ("b.png", "r.png"):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.png", "r.png"]  # no temporaries


BAD = [
    (["--set", "mass=-4"], "mass"),
    (["--set", "piston_area=0"], "piston_area"),
    (["--set", "Kv=nan"], "Kv"),
    (["--set", "bogus=1"], "bogus"),
    (["--set", "loop_time=3 psi"], "loop_time"),
    (["--table", "/nonexistent/table.toml"], "table.toml"),
]


@pytest.mark.parametrize("args, key", [BAD[0], BAD[5]])
def test_bad_input_one_line_exit_2_subprocess(args, key):
    res = subprocess.run([str(IMIL), "table", "poles", *args], capture_output=True, text=True, timeout=60)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0] and "Traceback" not in res.stderr
    assert res.stdout == ""


@pytest.mark.parametrize("args, key", BAD[1:5])
def test_bad_input_names_the_key(args, key):
    # The library raises ConfigError naming the key; main.run() prints it on one line (above).
    with pytest.raises(Exception, match=key):
        runner.invoke(app, ["table", "poles", *args], catch_exceptions=False)


def test_bad_choices_direct():
    with pytest.raises(Exception, match="output"):
        runner.invoke(app, ["table", "tf", "--output", "q"], catch_exceptions=False)
    with pytest.raises(Exception, match="delay"):
        runner.invoke(app, ["table", "poles", "--delay", "exact"], catch_exceptions=False)


def test_demo_writes_plots(tmp_path):
    res = runner.invoke(app, ["demo", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    assert "stable: yes" in res.stdout
    assert {p.name for p in tmp_path.glob("*.png")} >= {"table_bode.png", "table_rlocus_Ke.png"}


def test_tune_prints_the_reports_figures_only_for_the_reports_table(tmp_path):
    needle = "report Section 4.4"
    assert needle in runner.invoke(app, ["table", "tune"]).stdout
    # The report's table copied elsewhere is still the report's; with a value changed it is not.
    copy = tmp_path / "mine.toml"
    copy.write_text(default_table_path().read_text())
    assert needle in runner.invoke(app, ["table", "tune", "--table", str(copy)]).stdout
    changed = runner.invoke(app, ["table", "tune", "--table", str(copy), "--set", "mass=1600 lb"])
    assert changed.exit_code == 0 and needle not in changed.stdout and "Kp_limit" in changed.stdout
    assert needle not in runner.invoke(app, ["table", "tune", "--set", "Ke=4"]).stdout


# ---------------------------------------------------------------- LTI tables (issue 13)
def _lti_file(tmp_path, kind: str, delay: str = "first-order") -> Path:
    """The report's table (its first-order model, the delay "included") as an LTI table file of ``kind``."""
    model = LinearTable(TableParameters.report_default()).state_space().system
    table = LTITable.from_control(model.to_control(), 5e-4, "included")
    text = lti_table_toml(table, kind).replace('delay = "included"', f'delay = "{delay}"')
    path = tmp_path / f"{kind}.toml"
    path.write_text(text)
    return path


KINDS = ["transfer-function", "zpk", "state-space"]


@pytest.mark.parametrize("kind", KINDS)
def test_lti_table_poles_tf_info_bode(tmp_path, kind):
    path = _lti_file(tmp_path, kind, "included")
    poles = _json(["table", "poles", "--table", str(path), "--json"])
    assert poles["delay"] == "included" and poles["stable"] is True
    got = np.sort_complex(np.array([complex(r["real"], r["imag"]) for r in poles["poles"]]))
    ref = np.sort_complex(LinearTable(TableParameters.report_default()).poles())
    np.testing.assert_allclose(got, ref, rtol=1e-9)  # measured 1e-15
    tf = _json(["table", "tf", "--table", str(path), "--input", "u", "--output", "z", "--json"])
    H = LinearTable(TableParameters.report_default()).tf("z", "u")
    np.testing.assert_allclose(tf["num"], H.num, rtol=1e-9)
    np.testing.assert_allclose(tf["den"], H.den, rtol=1e-9)
    assert tf["num"][-2:] == [0.0, 0.0]
    info = _json(["table", "info", "--table", str(path), "--json"])
    assert info["kind"] == kind and info["loop_time"] == pytest.approx(5e-4)
    assert info["dc_gains"]["x/u"] == pytest.approx(1.0, rel=1e-12) and info["force_path"] is True
    si = _json(["table", "info", "--table", str(path), "--json", "--units", "si"])
    assert si["dc_gains"]["x/w"] == pytest.approx(
        info["dc_gains"]["x/w"] * 25.4 / 4.4482216152605e-3, rel=1e-12
    )
    out = tmp_path / "bode.png"
    assert _json(["table", "bode", "--table", str(path), "-o", str(out), "--json"])["file"] == str(out)
    assert out.stat().st_size > 0


def test_lti_table_delay_adds_the_command_lag(tmp_path):
    data = _json(["table", "poles", "--table", str(_lti_file(tmp_path, "zpk")), "--json"])
    assert data["delay"] == "first-order" and len(data["poles"]) == 6
    assert min(r["real"] for r in data["poles"]) == pytest.approx(-1.0 / 5e-4, rel=1e-12)


@pytest.mark.parametrize("kind", KINDS)
def test_design_and_export_of_an_lti_table(tmp_path, kind):
    # The LTI file of the report's first-order model designs the report's controller.
    path = _lti_file(tmp_path, kind, "included")
    design = tmp_path / "d.json"
    doc = _json(["design", "--table", str(path), "--vs", "SD2", "--fc", "80", "--json", "-o", str(design)])
    ref = _json(["design", "--vs", "SD2", "--fc", "80", "--json"])
    for name in ("H_uz", "H_uw"):
        np.testing.assert_allclose(doc[name]["num"], ref[name]["num"], rtol=1e-9)  # measured 2e-15
        np.testing.assert_allclose(doc[name]["den"], ref[name]["den"], rtol=1e-9)
        assert len(doc["zpk"][name]["poles"]) == len(doc[name]["den"]) - 1
    mine, theirs = doc["constraints"][0], ref["constraints"][0]
    assert (mine["I"], mine["II"], mine["III"]) == (theirs["I"], theirs["II"], theirs["III"])
    assert mine["performance_error"] == pytest.approx(theirs["performance_error"], rel=1e-9)
    res = runner.invoke(app, ["export", str(design), "--format", "json", "-o", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "out" / "imil_coefficients.json").is_file()


@pytest.mark.parametrize(
    "args, key",
    [
        (["table", "tune"], "--table"),
        (["table", "rlocus"], "--table"),
        (["table", "poles", "--set", "Ke=3"], "--set"),
        (["table", "poles", "--delay", "pade"], "--delay"),
        (["table", "tf", "--output", "spool"], "--output"),
        (["design", "--vs", "SD2", "--fc", "80", "--method", "optimized"], "--method"),
    ],
)
def test_commands_needing_the_physical_table_refuse_an_lti_one(tmp_path, imil, args, key):
    path = _lti_file(tmp_path, "transfer-function")
    head = 2 if args[0] == "table" else 1
    res = imil(*args[:head], "--table", str(path), *args[head:])
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1 and key in lines[0], res.stderr
    assert "Traceback" not in res.stderr


def test_design_refuses_an_lti_table_without_force_path(tmp_path, imil):
    H = LinearTable(TableParameters.report_default()).tf("z", "u")
    path = tmp_path / "no_w.toml"
    path.write_text(
        '[model]\nkind = "transfer-function"\nloop_time = "500 us"\ndelay = "first-order"\n'
        'units = { z = "in/s**2", u = "in" }\n'
        f"H_zu = {{ num = {[float(c) for c in H.num]}, den = {[float(c) for c in H.den]} }}\n"
    )
    for form in ("standardized", "tracking"):
        res = imil("design", "--table", path, "--vs", "SD2", "--fc", "80", "--form", form)
        assert res.returncode == 2 and res.stderr.strip().count("\n") == 0 and "H_zw" in res.stderr


#: A general physical table (issue 13 item 1): tests/data/first_order_table.toml.
FIRST_ORDER_TABLE = (Path(__file__).parents[1] / "data" / "first_order_table.toml").read_text()


def test_first_order_table_poles_and_info(tmp_path):
    f = tmp_path / "first.toml"
    f.write_text(FIRST_ORDER_TABLE)
    data = _json(["table", "poles", "--table", str(f), "--json"])
    p = TableParameters.from_toml(f)
    assert len(data["poles"]) == 4 and data["stable"] is True  # four states: one valve pole
    got = np.sort_complex(np.array([complex(r["real"], r["imag"]) for r in data["poles"]]))
    np.testing.assert_allclose(got, np.sort_complex(LinearTable(p).poles()), rtol=1e-12)
    assert {r["label"] for r in data["poles"]} == {"p1", "p2", "p4", "p5"}
    info = _json(["table", "info", "--table", str(f), "--json"])["parameters"]
    assert info["valve"] == "first-order" and info["valve_time_constant"] == pytest.approx(0.0246)
    assert info["platen_damping"] == 5.0 and info["grounded_stiffness"] == 300.0
    assert "valve_poles_hz" not in info and info["d"] == pytest.approx(p.d)  # d from the ratings
    res = runner.invoke(app, ["table", "info", "--table", str(f)])
    assert res.exit_code == 0 and "valve_time_constant" in res.stdout and "first-order" in res.stdout


def test_a_key_of_another_valve_kind_is_refused_naming_it(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(FIRST_ORDER_TABLE + 'valve_poles_hz = ["70 Hz", "110 Hz"]\n')
    res = subprocess.run(
        [str(IMIL), "table", "poles", "--table", str(f)], capture_output=True, text=True, timeout=120
    )
    assert res.returncode == 2 and res.stdout == ""
    assert (
        res.stderr.count("\n") == 1 and "valve_poles_hz: expected no key of another valve kind" in res.stderr
    )
