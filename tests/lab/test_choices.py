"""Experiment descriptions from partial choices: defaults from the report's setup, listed; one feedback vocabulary."""

from __future__ import annotations

import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.choices import Choices, frf_test, mil_test, tracking_test
from impedance_mil.lab.feedback import Feedback
from impedance_mil.plant import TableParameters, default_table_path
from impedance_mil.report_config import report_config
from impedance_mil.units import G0
from impedance_mil.virtual import presets


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


def test_a_chosen_motion_runs_as_recorded_and_only_the_default_is_time_compressed(tmp_path):
    # A user's file: time scale 1 (its own 0.01 s interval), nothing listed from [motion].
    rows = "\n".join(f"{0.01 * k:.2f},{0.1 * (k % 7)}" for k in range(400))
    (tmp_path / "m.csv").write_text("time,accel[g]\n" + rows + "\n")
    user = tracking_test(Choices(motion=str(tmp_path / "m.csv")))
    assert user.motion.time_scale == 1.0 and user.motion.motion.time_step == pytest.approx(0.01, rel=1e-12)
    assert not {"motion.time_scale", "motion.record"} & set(user.from_report)
    # A chosen built-in record too (the report's seed itself, as recorded: dt 0.01 s).
    seed = tracking_test(Choices(motion="elcentro", duration=2.0))
    assert seed.motion.time_scale == 1.0 and "motion.time_scale" not in seed.from_report
    assert seed.motion.motion.time_step == pytest.approx(0.01, rel=1e-12)
    # The report's default motion takes [motion] time_scale, listed; an explicit one wins.
    default = tracking_test(Choices(duration=2.0))
    assert (
        default.motion.time_scale
        == report_config().motion.time_scale
        == default.from_report["motion.time_scale"]
    )
    assert default.motion.motion.time_step == pytest.approx(
        0.01 / report_config().motion.time_scale, rel=1e-12
    )
    chosen = tracking_test(Choices(motion=str(tmp_path / "m.csv"), time_scale=4.0))
    assert chosen.motion.motion.time_step == pytest.approx(0.0025, rel=1e-12)


def test_a_column_file_without_a_unit_needs_motion_units(tmp_path):
    rows = "\n".join(f"{0.01 * k:.2f},{0.1 * (k % 7)}" for k in range(400))
    (tmp_path / "m.csv").write_text(rows + "\n")
    keys = {"motion_units": "--motion-units"}
    with pytest.raises(ConfigError, match="^--motion-units: expected the unit of the accelerations of m.csv"):
        tracking_test(Choices(motion=str(tmp_path / "m.csv"), keys=keys))
    test = tracking_test(Choices(motion=str(tmp_path / "m.csv"), motion_units="m/s**2", keys=keys))
    # 0.6 m/s^2 peak = 0.6 / 9.80665 g (exact conversion).
    assert test.motion.motion.pga_g == pytest.approx(0.6 / 9.80665, rel=1e-12)
    with pytest.raises(ConfigError, match="^--motion-units"):
        tracking_test(Choices(motion_units="parsec", keys=keys))  # refused for the built-in motion too


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


def test_a_preset_carries_the_specimen_actually_used():
    # The FP's axial load W = m_vs g + w_ps (Eq 5-9b, Figure 7.11) follows a 20,000 lb rigid article;
    # k_s stays the preset's (Table 9.3: from T_s with the report's article), and the run says so.
    cfg = report_config()
    heavy = mil_test(Choices(vs="FP2", specimen="rigid", specimen_weight="20000 lbf", duration=1.0))
    values, preset = heavy.vs_spec.vs.to_dict(), presets.get("FP2").to_dict()
    assert values["w_ps"] == 20000.0 and values["W"] == pytest.approx(
        preset["m_vs"] * G0 + 20000.0, rel=1e-12
    )
    assert values["k_s"] == preset["k_s"]
    (note,) = heavy.vs_spec.notes
    assert f"{cfg.specimen.article_weight_lbf:g} lbf" in note and "20000 lbf" in note and "w_ps" in note
    assert heavy.pretest().basemat is not None  # no longer refused over the report's 3600 lbf
    # The report's own article (its vessel at 36 in) weighs the report's 3600 lbf: the preset is unchanged.
    report = mil_test(Choices(vs="FP2", duration=1.0))
    assert report.vs_spec.vs.to_dict() == preset and report.vs_spec.notes == ()
    assert report.from_report["specimen.article_weight"] == cfg.specimen.article_weight_lbf
    # A type without an axial load (SD) keeps its parameters; its targets' article is named.
    bare = mil_test(Choices(vs="SD2", specimen="none", duration=1.0))
    assert bare.vs_spec.vs.to_dict() == presets.get("SD2").to_dict()
    assert "weighs 0 lbf" in bare.vs_spec.notes[0] and "axial" not in bare.vs_spec.notes[0]
    # A w_ps the user sets is kept, without a note.
    chosen = mil_test(Choices(vs="FP2", specimen="rigid", specimen_weight=2000, vs_overrides={"w_ps": 2500}))
    assert chosen.vs_spec.vs.to_dict()["w_ps"] == 2500.0 and chosen.vs_spec.notes == ()


def test_a_labs_output_delay_and_filters_reach_the_run(tmp_path):
    # Issue 12: [controller] output_delay and [sensors.NAME] bandwidth are the lab's, and the
    # run's LabChoice (what experiments pass to simulate) carries them; the report's is 1 loop.
    lab = tmp_path / "l.toml"
    lab.write_text(
        f'[table]\nfile = "{default_table_path()}"\n[controller]\noutput_delay = "3 loops"\n'
        '[sensors.x]\nquantity = "displacement"\nrange = "4 in"\nbandwidth = "250 Hz"\n'
        '[sensors.z]\nquantity = "acceleration"\nrange = "5 g0"\n'
        '[sensors.dp]\nquantity = "differential_pressure"\nrange = "3000 psi"\n'
    )
    test = tracking_test(Choices(lab=str(lab), feedback="fe"))
    assert test.lab.output_delay == 3
    assert [s.bandwidth_hz for s in test.lab.sensors.sensors] == [250.0, None, None]
    assert tracking_test(Choices()).lab.output_delay == 1
