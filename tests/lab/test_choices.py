"""Experiment descriptions from partial choices: defaults from the report's setup, listed; one feedback vocabulary."""

from __future__ import annotations

import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.choices import Choices, frf_test, mil_test, tracking_test
from impedance_mil.lab.feedback import Feedback
from impedance_mil.plant import TableParameters, default_table_path
from impedance_mil.report_config import report_config


def test_every_value_nobody_chose_comes_from_the_report_and_is_listed():
    test = tracking_test(Choices(duration=2.0))
    cfg = report_config()
    used = test.from_report
    assert used["design.fc"] == test.controller.fc_hz == cfg.design.fc_hz
    assert used["controller.feedback"] == test.controller.feedback.value == "lc"
    assert used["specimen.water_depth"] == 36.0 and test.specimen.specimen.water_depth_in == 36.0
    assert used["motion.time_scale"] == test.motion.time_scale == 2.0
    assert used["motions.GM1.pga"] == test.motion.pga_g == 0.8  # Table 8.1
    assert test.motion.motion.pga_g == pytest.approx(0.8, rel=1e-12)
    assert test.table == TableParameters.report_default() and used["table.file"] == default_table_path().name
    assert test.lab.limits.stroke == used["limits.stroke"] == 3.0


def test_a_chosen_value_is_not_listed():
    test = tracking_test(Choices(fc_hz="0.1 kHz", pga_g=0.3, water_depth="0.5 m", duration=2.0))
    assert test.controller.fc_hz == pytest.approx(100.0, rel=1e-12)
    assert test.specimen.specimen.water_depth_in == pytest.approx(0.5 / 0.0254, rel=1e-12)
    assert not {"design.fc", "specimen.water_depth", "motions.GM1.pga"} & set(test.from_report)
    assert test.motion.motion.pga_g == pytest.approx(0.3, rel=1e-12)


def test_ratings_a_table_file_leaves_out_are_the_reports_and_listed(tmp_path):
    text = default_table_path().read_text().replace('supply_pressure = "3000 psi"', "")
    (tmp_path / "t.toml").write_text(text)
    test = tracking_test(Choices(table=tmp_path / "t.toml", duration=2.0))
    assert test.table.supply_pressure == 3000.0 and test.from_report["table.supply_pressure"] == 3000.0
    assert "table.file" not in test.from_report and "table.rated_flow" not in test.from_report


def test_errors_name_the_choice_as_the_caller_calls_it():
    keys = {"water_depth": "--water-depth", "feedback": "--feedback", "seed": "--seed", "precision": "--p"}
    for choices, name in (
        (Choices(water_depth="3 kg", keys=keys), "--water-depth"),
        (Choices(feedback="xx", keys=keys), "--feedback"),
        (Choices(seed=-1, keys=keys), "--seed"),
        (Choices(precision="half", keys=keys), "--p"),
    ):
        with pytest.raises(ConfigError, match=name):
            tracking_test(choices)
    with pytest.raises(ConfigError, match="--feedback"):
        mil_test(Choices(feedback="none", keys=keys))  # a MIL run feeds the measured force to the VS
    with pytest.raises(ConfigError, match="kp_study"):
        frf_test(Choices(specimen="vessel"), kp_study=True)


def test_one_feedback_vocabulary_and_the_old_spellings():
    assert [f.value for f in Feedback] == ["lc", "fe", "none"]
    assert Feedback.parse("load_cells") is Feedback.parse("lc") is Feedback.LOAD_CELLS
    assert Feedback.parse("force_equilibrium") is Feedback.FORCE_EQUILIBRIUM
    assert (Feedback.NONE.channel, Feedback.NONE.compensates) == ("lc", False)
    assert (Feedback.FORCE_EQUILIBRIUM.channel, Feedback.LOAD_CELLS.compensates) == ("fe", True)
    with pytest.raises(ConfigError, match="--feedback"):
        Feedback.parse("none", "--feedback", allow_none=False)


def test_a_duration_longer_than_the_motion_is_refused_not_cut_to_it():
    # --duration 1e308 ran the whole record (about a minute) instead of being refused (issue 18).
    whole = tracking_test(Choices()).motion.motion
    keys = {"duration": "--duration", "specimen_weight": "--specimen-weight"}
    for too_long in (1e308, whole.duration + 2 * whole.time_step):
        with pytest.raises(
            ConfigError, match=f"--duration: expected at most the motion's length, {whole.duration:.6g} s"
        ):
            tracking_test(Choices(duration=too_long, keys=keys))
    exact = tracking_test(Choices(duration=whole.duration)).motion.motion
    assert exact.duration == whole.duration and len(exact.accel) == len(whole.accel)


def test_a_rigid_weight_beyond_the_plausibility_bound_is_refused_naming_the_option():
    keys = {"specimen_weight": "--specimen-weight", "specimen": "--specimen"}
    with pytest.raises(
        ConfigError, match="--specimen-weight: expected a plausible value, at most 1e\\+09 lbf"
    ):
        tracking_test(Choices(specimen="rigid", specimen_weight="1e308 lbf", duration=2.0, keys=keys))
