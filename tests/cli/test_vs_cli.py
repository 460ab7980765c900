"""`imil vs` commands, run in-process through the real entry point (exit codes included)."""

import json
import sys

import pytest

from impedance_mil.cli import main


def _imil(monkeypatch, capsys, *args):
    monkeypatch.setattr(sys, "argv", ["imil", "vs", *args])
    with pytest.raises(SystemExit) as exc:
        main.run()
    out = capsys.readouterr()
    return (exc.value.code or 0), out.out, out.err


def test_list(monkeypatch, capsys):
    code, out, _ = _imil(monkeypatch, capsys, "list", "--json")
    assert code == 0
    rows = json.loads(out)
    names = [r["name"] for r in rows]
    assert names[:9] == ["SD1", "SD2", "SD3", "LR1", "LR2", "LR3", "FP1", "FP2", "FP3"]
    assert names[9:] == ["TFP1", "TFP2", "TFP3"]
    tfp = rows[9]
    assert tfp["kind"] == "TFP" and tfp["mu2"] == 0.012 and tfp["k_s"] is None


def test_describe_json_keys_as_in_tables(monkeypatch, capsys):
    code, out, _ = _imil(monkeypatch, capsys, "describe", "LR2", "--json")
    assert code == 0
    data = json.loads(out)
    for key in ("m_vs", "k_s", "c", "q_d", "k_i", "alpha", "u_y", "n"):
        assert key in data and key in data["units"]
    assert data["units"]["k_i"] == "lbf/in"
    assert abs(data["q_d"] - 839) <= 1 + 0.839  # Table 9.2, tolerance of tests/virtual/test_presets.py
    code, out, _ = _imil(monkeypatch, capsys, "describe", "FP2", "--json")
    data = json.loads(out)
    for key in ("mu_max", "mu_min", "a", "W", "k_s", "k_i", "u_y", "m_vs"):
        assert key in data
    assert data["W"] == pytest.approx(5600.0)


def test_describe_with_units_in_set(monkeypatch, capsys):
    code, out, _ = _imil(
        monkeypatch, capsys, "describe", "FP1", "--json", "--set", "m_vs=2150 lb", "--set", "u_y=1 mm"
    )
    assert code == 0
    data = json.loads(out)
    assert data["W"] == pytest.approx(5750.0)
    assert data["u_y"] == pytest.approx(1 / 25.4)


def test_describe_file(monkeypatch, capsys, tmp_path):
    f = tmp_path / "my_lr.toml"
    f.write_text('kind = "LR"\nq_ratio = 0.1\nT_s = "2 s"\nu_y = "10 mm"\nc = 0.2\nm_vs = "1500 lb"\n')
    code, out, _ = _imil(monkeypatch, capsys, "describe", str(f), "--json")
    assert code == 0
    data = json.loads(out)
    assert data["q_d"] == pytest.approx(0.1 * 5100.0)  # (1500 + 3600) lb total weight
    assert data["u_y"] == pytest.approx(10 / 25.4)


@pytest.mark.parametrize(
    "args, key",
    [
        (("describe", "XX1"), "preset"),
        (("describe", "SD1", "--set", "m_vs=0"), "m_vs"),
        (("describe", "SD1", "--set", "k_s=-5"), "k_s"),
        (("describe", "FP1", "--set", "mu_min=0.2"), "mu_min"),
        (("describe", "LR1", "--set", "u_y=0"), "u_y"),
        (("describe", "LR1", "--set", "u_y=3 s"), "u_y"),
        (("describe", "LR1", "--set", "bogus=1"), "bogus"),
    ],
)
def test_bad_input_exit_2_one_line(monkeypatch, capsys, args, key):
    code, out, err = _imil(monkeypatch, capsys, *args)
    assert code == 2
    assert err.count("\n") == 1 and key in err and "Traceback" not in err
    assert out == ""


def test_loops_writes_png(monkeypatch, capsys, tmp_path):
    target = tmp_path / "loops.png"
    code, out, _ = _imil(
        monkeypatch,
        capsys,
        "loops",
        "LR2",
        "FP2",
        "-o",
        str(target),
        "--json",
        "--cycles",
        "1",
        "--amplitude",
        "0.2 g0",
        "--frequency",
        "1.0",
    )
    assert code == 0
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    summary = json.loads(out)
    assert [s["name"] for s in summary["systems"]] == ["LR2", "FP2"]
    assert all(s["dissipated_energy"] > 0 for s in summary["systems"])


def test_loops_bad_input_writes_nothing(monkeypatch, capsys, tmp_path):
    target = tmp_path / "loops.png"
    code, _, err = _imil(monkeypatch, capsys, "loops", "LR2", "-o", str(target), "--set", "n=-2")
    assert code == 2 and "n" in err
    code, _, err = _imil(monkeypatch, capsys, "loops", "LR2", "-o", str(tmp_path / "loops.xyz"))
    assert code == 2 and "-o" in err
    assert list(tmp_path.iterdir()) == []


def test_loops_recorded_motion(monkeypatch, capsys, tmp_path):
    """A built-in record (signals package) held over sub-steps no longer than --dt."""
    target = tmp_path / "elcentro.svg"
    code, out, _ = _imil(
        monkeypatch,
        capsys,
        "loops",
        "SD2",
        "--motion",
        "elcentro",
        "--pga",
        "0.2",
        "-o",
        str(target),
        "--json",
        "--dt",
        "0.001",
    )
    assert code == 0 and target.exists()
    summary = json.loads(out)
    assert summary["dt"] <= 0.001
    # SD2 with the article: peak z_vs is of the order of the PGA (0.2 g = 77 in/s^2)
    assert 20.0 < summary["systems"][0]["peak_z_vs"] < 200.0


def test_loops_fp_carries_an_article_heavier_than_the_reports(monkeypatch, capsys, tmp_path):
    # FP2's axial load W = m_vs g + w_ps follows --article-weight (it was refused over w_ps = 3600 lbf):
    # the summary's axial load is basemat (2000 lb) plus article, and a note names the targets' article.
    code, out, err = _imil(
        monkeypatch,
        capsys,
        "loops",
        "FP2",
        "--article-weight",
        "20000 lbf",
        "-o",
        str(tmp_path / "l.svg"),
        "--json",
    )
    assert code == 0
    (row,) = json.loads(out)["systems"]
    assert row["axial_load"] == pytest.approx(22000.0, rel=1e-9)
    assert "3600 lbf" in err and "20000 lbf" in err and "w_ps" in err
