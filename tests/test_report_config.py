"""The report's setup file (data/report/config.toml): its values, that the code reads it, bad files."""

from __future__ import annotations

import shutil

import pytest

from impedance_mil.design import design_controller, table_model
from impedance_mil.errors import ConfigError
from impedance_mil.plant import TableParameters, default_table_path
from impedance_mil.report_config import REPORT_CONFIG_PATH, load_config, report_config
from impedance_mil.virtual import TEST_ARTICLE_WEIGHT


def test_the_reports_values():
    cfg = report_config()
    # Sections 8.3 and 9.3: f_c = 80 Hz, standardized form, Butterworth filters (Eq 6-10).
    assert (cfg.design.fc_hz, cfg.design.form, cfg.design.filter) == (80.0, "standardized", "butterworth")
    # Section 9.2 / Table 9.1: 36 in of water; Tables 9.1-9.3: the 3600 lbf article.
    assert cfg.specimen.water_depth_in == 36.0 and cfg.specimen.article_weight_lbf == 3600.0
    # Section 8.2: seeds time-compressed by 2; Table 8.1: 0.8, 0.6, 0.4 g; +-3 in of stroke.
    assert cfg.motion.time_scale == 2.0 and cfg.default_motion.name == "GM1"
    assert {n: m.pga_scaled_g for n, m in cfg.motions.items()} == {"GM1": 0.8, "GM2": 0.6, "GM3": 0.4}
    assert [m.rsn for m in cfg.motions.values()] == [6, 864, 2632]
    assert cfg.limits.stroke_in == 3.0 and cfg.controller.feedback == "lc"
    # Section 4.5.2: 0.1 in multisine peak; Sections 4.5.3.1 / 8.3.3: the K_p study.
    assert cfg.frf.peak_in == 0.1 and cfg.frf.kp_values == (0.0002, 0.0006, 0.001, 0.0014)
    # The table is the Table 4.1 file, and the report's article is read from here.
    assert cfg.table_file == default_table_path() and TEST_ARTICLE_WEIGHT == 3600.0
    assert TableParameters.report_default().loop_time == 0.0005
    # Section 4.4's printed tuning figures (imil table tune shows them for the report's table).
    t = cfg.tuning
    assert (t.ke_limit, t.kp_limit, t.breakaway_ke, t.breakaway_kp) == (6.7, 0.0035, 39.3, 0.0006)
    assert t.chosen_kp == TableParameters.report_default().Kp == 0.001


def test_the_code_reads_the_file(tmp_path):
    # A copy with another cut-off: load_config reads it (nothing of it is typed in the code).
    (tmp_path / "tables").mkdir()
    shutil.copy(default_table_path(), tmp_path / "tables" / default_table_path().name)
    (tmp_path / "report").mkdir()
    text = REPORT_CONFIG_PATH.read_text().replace('fc = "80 Hz"', 'fc = "0.1 kHz"')
    (tmp_path / "report" / "config.toml").write_text(text)
    cfg = load_config(tmp_path / "report" / "config.toml")
    assert cfg.design.fc_hz == pytest.approx(100.0, rel=1e-12)
    assert cfg.table_file == (tmp_path / "tables" / default_table_path().name).resolve()


@pytest.mark.parametrize(
    "old, new, key",
    [
        ("\n[vs]\n", "\n[bogus]\n[vs]\n", "[bogus]"),
        ('fc = "80 Hz"', 'fc = "80 in"', "design.fc"),
        ('water_depth = "36 in"', "", "specimen.water_depth"),
        ('record = "GM1"', 'record = "GM9"', "motion.record"),
        ('substeps = "auto"', "substeps = 0", "controller.substeps"),
        ("rsn = 864", "rsn = -1", "motions.GM2.rsn"),
        ('ke_limit = "6.7 V/in"', 'ke_limit = "6.7 V/psi"', "tuning.ke_limit"),
    ],
)
def test_a_bad_file_is_refused_naming_the_key(tmp_path, old, new, key):
    path = tmp_path / "config.toml"
    path.write_text(REPORT_CONFIG_PATH.read_text().replace(old, new, 1))
    with pytest.raises(ConfigError, match=key.replace("[", r"\[").replace("]", r"\]")):
        load_config(path)


def test_design_controller_takes_the_cut_off():
    # No cut-off is written in its signature: it must be given.
    with pytest.raises(TypeError, match="fc_hz"):
        design_controller(table_model(TableParameters.report_default()))  # type: ignore[call-arg]
