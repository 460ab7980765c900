"""Campaign files: expansion, validation and refusal of bad input before anything runs."""

from __future__ import annotations

import pytest

from impedance_mil.campaign import builtin_campaigns, load_campaign
from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.units import G0

HEAD = '[campaign]\nname = "t"\nkind = "selftest"\n'


def test_product_zip_cases_expand_to_their_cartesian_product(make_campaign):
    path = make_campaign(
        HEAD
        + """
[[study]]
name = "a"
cases = [ { fail = false }, { fail = true } ]
product = { stiffness = [100, 200, 300] }
zip = { damping = [1, 2], delay = [0, 0] }
"""
    )
    spec = load_campaign(path)
    # 2 cases x 3 stiffnesses x 2 zipped rows = 12 distinct configurations.
    assert len(spec.runs) == 12
    combos = {(r.settings["fail"], r.settings["stiffness"], r.settings["damping"]) for r in spec.runs}
    assert len(combos) == 12
    assert spec.parameters == ("fail", "stiffness", "damping", "delay")


def test_units_are_converted_to_the_report_units(make_campaign):
    path = make_campaign(
        HEAD
        + """
[base]
mass = "5600 lb"
[[study]]
name = "a"
product = { stiffness = ["894 lbf/in", "156.56 N/mm"] }
"""
    )
    spec = load_campaign(path)
    # 5600 lb of mass = 5600 / g0 lbf*s^2/in (exact definition, units.py).
    assert spec.runs[0].config["oscillator"]["mass"] == pytest.approx(5600 / G0, rel=1e-12)
    # 156.56 N/mm = 156.56 / 4.4482216 * 25.4 lbf/in = 894.0 lbf/in (NIST factors), to 1e-4.
    assert spec.runs[1].settings["stiffness"] == pytest.approx(894.0, rel=1e-4)


def test_a_run_asked_for_by_two_studies_runs_once(make_campaign):
    path = make_campaign(
        HEAD
        + """
[[study]]
name = "a"
product = { stiffness = [100, 200] }
[[study]]
name = "b"
product = { stiffness = [200, 300] }
"""
    )
    spec = load_campaign(path)
    assert len(spec.runs) == 3
    shared = [r for r in spec.runs if r.settings["stiffness"] == 200.0]
    assert len(shared) == 1 and shared[0].studies == ("a", "b")


def test_reduced_version_replaces_lists_and_drops_studies(make_campaign):
    path = make_campaign(
        HEAD
        + """
[reduced.base]
damping = 7
[[study]]
name = "keep"
product = { stiffness = [100, 200, 300] }
reduced = { stiffness = [100] }
[[study]]
name = "drop"
product = { stiffness = [400, 500] }
reduced = false
"""
    )
    full, small = load_campaign(path), load_campaign(path, reduced=True)
    assert len(full.runs) == 5
    assert len(small.runs) == 1 and small.runs[0].settings == {"damping": 7.0, "stiffness": 100.0}
    assert small.reduced and not full.reduced


def test_overrides_apply_to_every_run_and_change_the_run_ids(sd_campaign):
    plain = load_campaign(sd_campaign)
    heavier = load_campaign(sd_campaign, overrides={"mass": "6000 lb"})
    assert all(r.settings["mass"] == pytest.approx(6000 / G0) for r in heavier.runs)
    assert not {r.run_id for r in plain.runs} & {r.run_id for r in heavier.runs}


@pytest.mark.parametrize(
    "body, key, expected",
    [
        (
            '[[study]]\nname = "a"\nproduct = { stifness = [1] }\n',
            "study.a.product.stifness",
            "a known parameter",
        ),
        (
            '[[study]]\nname = "a"\nproduct = { stiffness = [] }\n',
            "study.a.product.stiffness",
            "a non-empty list",
        ),
        (
            '[[study]]\nname = "a"\nproduct = { stiffness = ["3 in"] }\n',
            "study.a.product.stiffness",
            "dimension",
        ),
        (
            '[base]\nmass = "2 in"\n[[study]]\nname = "a"\nproduct = { stiffness = [1] }\n',
            "base.mass",
            "dimension",
        ),
        ('[[study]]\nname = "a"\nproduct = { stiffness = [-5] }\n', "study.a.product.stiffness", "positive"),
        (
            '[[study]]\nname = "a"\nzip = { stiffness = [1, 2], damping = [1] }\n',
            "study.a.zip",
            "equal length",
        ),
        (
            '[[study]]\nname = "a"\nset = { damping = 1 }\nproduct = { damping = [2] }\n',
            "study.a.damping",
            "only one",
        ),
        ('[[study]]\nname = "a"\nproduct = { fail = ["yes"] }\n', "study.a.product.fail", "true or false"),
        ('[[study]]\nname = "a"\nprodukt = { stiffness = [1] }\n', "study.a.produkt", "one of the keys"),
        ("", "study", "at least one"),
    ],
)
def test_bad_campaigns_are_refused_with_the_key_named(make_campaign, body, key, expected):
    with pytest.raises(ConfigError) as info:
        load_campaign(make_campaign(HEAD + body))
    assert info.value.key == key
    assert expected in str(info.value)
    assert "\n" not in str(info.value)


def test_unknown_kind_is_refused(make_campaign):
    path = make_campaign('[campaign]\nname = "t"\nkind = "mill"\n[[study]]\nname = "a"\n')
    with pytest.raises(ConfigError, match="campaign.kind"):
        load_campaign(path)


def test_more_runs_than_max_runs_is_refused_before_expansion(make_campaign):
    # 100**4 = 1e8 runs would exhaust memory if expanded; the count is checked first.
    values = list(range(1, 101))
    path = make_campaign(
        HEAD
        + f"""
[[study]]
name = "huge"
product = {{ stiffness = {values}, damping = {values}, mass = {values}, delay = {values} }}
"""
    )
    with pytest.raises(ConfigError, match=r"--max-runs: expected at most 10000 runs, got '100000000 runs"):
        load_campaign(path)
    with pytest.raises(ConfigError, match="at most 3 runs"):
        load_campaign(
            make_campaign(
                HEAD + '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2, 3, 4] }\n', "four.toml"
            ),
            max_runs=3,
        )


def test_missing_campaign_is_a_data_file_error(tmp_path):
    with pytest.raises(DataFileError, match="no such campaign file or built-in campaign"):
        load_campaign(tmp_path / "nope.toml")


@pytest.mark.parametrize("name", sorted(builtin_campaigns()))
def test_every_builtin_campaign_expands_in_full_and_reduced(name):
    full, reduced = load_campaign(name), load_campaign(name, reduced=True)
    assert 0 < len(reduced.runs) <= len(full.runs)
    assert len({r.run_id for r in full.runs}) == len(full.runs)
