"""VS files (TOML with units), overrides and validation (bad input -> ConfigError naming the key)."""

import pytest

from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.units import G0
from impedance_mil.virtual import FrictionPendulum, LeadRubber, SpringDamper, presets
from impedance_mil.virtual.files import describe, load, resolve


def _write(tmp_path, text, name="vs.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_model_parameters_file(tmp_path):
    spec = load(_write(tmp_path, 'kind = "SD"\nm_vs = "2000 lb"\nk_s = "894 lbf/in"\nc = 57\n'))
    assert spec.vs.kind == SpringDamper.kind == "SD" and spec.targets is None
    assert spec.vs.m_vs == pytest.approx(2000 / G0, rel=1e-12)  # pint: lb -> lbf*s^2/in exactly
    assert (spec.vs.k_s, spec.vs.c) == (894.0, 57.0)


def test_targets_file_equals_preset(tmp_path):
    spec = load(_write(tmp_path, 'kind = "FP"\nmu_max = 0.12\nmu_min = 0.06\nT_s = "1.75 s"\n'))
    assert spec.vs == presets.get("FP2")


def test_preset_file_with_change(tmp_path):
    spec = load(_write(tmp_path, 'preset = "LR2"\nc = "0.3 lbf*s/in"\n'))
    assert spec.vs == presets.get("LR2", c=0.3)


def test_overrides_accumulate():
    spec = resolve("SD2", {"m_vs": "1.25 * 4.14"})
    assert spec.vs.m_vs == pytest.approx(1.25 * 4.14)
    assert spec.vs.k_s == presets.get("SD2").k_s  # Section 9.4.4: only m_vs changes
    props = {p.key: p for p in describe(spec)}
    assert props["k_s"].unit == "force_pound / inch"
    assert props["f"].value == 1.25


@pytest.mark.parametrize(
    "text, key",
    [
        ('kind = "SD"\nm_vs = 0\nk_s = 1\nc = 1\n', "m_vs"),
        ('kind = "SD"\nm_vs = 1\nk_s = -1\nc = 1\n', "k_s"),
        ('kind = "LR"\nm_vs = 1\nk_i = 100\nalpha = 0.1\nq_d = 0\nc = 0\n', "q_d"),
        ('kind = "LR"\nq_ratio = 0.1\nT_s = 2\nu_y = 0\n', "u_y"),
        ('kind = "FP"\nmu_max = 0.05\nmu_min = 0.1\nT_s = 2\n', "mu_min"),
        ('kind = "XY"\n', "kind"),
        ('kind = "SD"\nf = 1\nzeta = 0.1\nk_i = 5\n', "k_i"),
        ('kind = "SD"\nm_vs = 1\nk_s = 1\n', "c"),
        ('preset = "LR9"\n', "preset"),
    ],
)
def test_bad_files_name_the_key(tmp_path, text, key):
    with pytest.raises(ConfigError) as exc:
        load(_write(tmp_path, text))
    assert key in str(exc.value) and "vs.toml" in str(exc.value)


def test_unreadable_file(tmp_path):
    with pytest.raises(DataFileError):
        load(_write(tmp_path, "kind = [unclosed\n"))


@pytest.mark.parametrize(
    "cls, kwargs, key",
    [
        (SpringDamper, dict(m_vs=-1.0, k_s=1.0, c=0.0), "m_vs"),
        (SpringDamper, dict(m_vs=1.0, k_s=0.0, c=0.0), "k_s"),
        (LeadRubber, dict(m_vs=1.0, k_i=10.0, alpha=1.0, q_d=1.0, c=0.0), "alpha"),
        (
            FrictionPendulum,
            dict(m_vs=1.0, k_s=1.0, mu_max=0.05, mu_min=0.06, a=1.0, u_y=0.04, w_ps=0.0),
            "mu_min",
        ),
        (
            FrictionPendulum,
            dict(m_vs=1.0, k_s=1.0, mu_max=0.05, mu_min=0.01, a=1.0, u_y=0.0, w_ps=0.0),
            "u_y",
        ),
    ],
)
def test_constructors_validate(cls, kwargs, key):
    with pytest.raises(ConfigError) as exc:
        cls(**kwargs)
    assert exc.value.key == key


def test_unknown_preset_and_override():
    with pytest.raises(ConfigError) as exc:
        presets.get("SD7")
    assert exc.value.key == "preset"
    with pytest.raises(ConfigError) as exc:
        presets.get("SD1", q_d=5.0)
    assert exc.value.key == "q_d"
