"""`imil campaign`: bad input is refused with one line and exit status 2, before anything runs."""

from __future__ import annotations

import json
import sys

import pytest

from impedance_mil.cli import campaign, main


@pytest.fixture
def imil(monkeypatch, capsys):
    """Run `imil campaign ...` in this process through main.run(); return (status, stdout, stderr)."""
    if not any(g.name == "campaign" for g in main.app.registered_groups):
        # The lead registers the sub-app in cli/main.py; until then the tests add it.
        monkeypatch.setattr(main.app, "registered_groups", list(main.app.registered_groups))
        main.app.add_typer(campaign.app, name="campaign")

    def call(*args):
        monkeypatch.setattr(sys, "argv", ["imil", "campaign", *map(str, args)])
        try:
            main.run()
            status = 0
        except SystemExit as exc:
            status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        captured = capsys.readouterr()
        return status, captured.out, captured.err

    return call


HEAD = '[campaign]\nname = "t"\nkind = "selftest"\n'


@pytest.mark.parametrize(
    "body, message",
    [
        (
            '[[study]]\nname = "a"\nproduct = { stifness = [1] }\n',
            "imil: error: study.a.product.stifness: expected a known parameter",
        ),
        (
            '[[study]]\nname = "a"\nproduct = { stiffness = [] }\n',
            "imil: error: study.a.product.stiffness: expected a non-empty list",
        ),
        (
            '[[study]]\nname = "a"\nproduct = { stiffness = ["2 s"] }\n',
            "imil: error: study.a.product.stiffness: expected a quantity with the dimension of force_pound / inch",
        ),
        (
            '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2, 3] }\n',
            "imil: error: --max-runs: expected at most 2 runs, got '3 runs",
        ),
    ],
)
def test_bad_campaign_exits_2_with_one_line_and_writes_nothing(imil, make_campaign, tmp_path, body, message):
    out = tmp_path / "out"
    status, _, err = imil("run", make_campaign(HEAD + body), "-o", out, "--max-runs", 2, "--workers", 0)
    assert status == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), err
    assert not out.exists()


def test_unreachable_scheduler_is_one_line_and_quick(imil, sd_campaign, tmp_path):
    # Port 9 (discard) is closed on localhost; a 1 s connect timeout bounds the wait.
    status, _, err = imil(
        "run", sd_campaign, "-o", tmp_path / "o", "--scheduler", "tcp://127.0.0.1:9", "--connect-timeout", 1
    )
    assert status == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "imil: error: --scheduler tcp://127.0.0.1:9: no Dask scheduler reachable within 1 s"
    ), err


def test_run_json_then_resume(imil, sd_campaign, tmp_path):
    status, out, err = imil("run", sd_campaign, "-o", tmp_path / "o", "--workers", 0, "--json")
    assert status == 0, err
    assert json.loads(out)["executed"] == 3
    second = json.loads(imil("run", sd_campaign, "-o", tmp_path / "o", "--workers", 0, "--json")[1])
    assert (second["executed"], second["skipped"], second["ok"]) == (0, 3, 3)


def test_plan_and_list(imil, sd_campaign):
    plan = json.loads(imil("plan", sd_campaign, "--json")[1])
    assert len(plan["runs"]) == 3 and plan["kind"] == "selftest"
    status, out, _ = imil("list")
    assert status == 0 and "selftest" in out


def test_report_command_writes_the_page(imil, sd_campaign, tmp_path):
    imil("run", sd_campaign, "-o", tmp_path / "o", "--workers", 0, "--json")
    status, out, err = imil("report", tmp_path / "o", "-o", tmp_path / "r.html")
    assert status == 0, err
    assert "not run" in out and (tmp_path / "r.html").read_text().startswith("<!DOCTYPE html>")
    status, _, err = imil("report", tmp_path / "missing", "-o", tmp_path / "r2.html")
    assert status == 2 and err.strip().count("\n") == 0 and "not a campaign folder" in err


def test_run_with_progress_bar_prints_a_summary(imil, sd_campaign, tmp_path):
    status, out, err = imil("run", sd_campaign, "-o", tmp_path / "o", "--workers", 0)
    assert status == 0, err
    assert "sd: 3 runs, 3 executed, 0 already done; ok 3, aborted 0, failed 0" in out
    assert "3/3" in out  # the progress bar's final state


def test_interrupt_exits_130_and_says_how_to_resume(imil, sd_campaign, tmp_path, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(campaign, "run_campaign", interrupted)
    status, _, err = imil("run", sd_campaign, "-o", tmp_path / "o", "--workers", 0, "--json")
    assert status == 130
    assert (
        err.strip() == f"imil: interrupted; finished runs are kept in {tmp_path / 'o'}; "
        "run the same command to resume"
    )
