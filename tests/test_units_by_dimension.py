"""Units that cannot be misread (issue 18, finding 4), for every key that parses through config.py.

The audit found ``f_oil_hz = "169.6 rad/s"`` read as 169.6 Hz, ``zeta = "20 percent"``
read as 20 and ``Ke = "500 percent"`` read as 500 V/in.  Each key family is
tested through its own entry point (table files and ``--set``, VS files and
``--set-vs``, specimen files, campaign parameters) with one invariant: the
key's current value written in another unit gives back exactly the same object
(to 1e-12, floating-point round-off of one conversion), namely

* a dimensionless key as ``100*v percent`` (percent is a fraction);
* a frequency key [Hz] as ``2*pi*v rad/s`` (an angular frequency is cycles
  times 2 pi, pint's radian being dimensionless), and as ``60*v rpm``;

and a key with a dimension given in percent, or a key other than a frequency
given with an angle, is refused with an error naming the key.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from impedance_mil.campaign.kinds import KINDS
from impedance_mil.config import quantity
from impedance_mil.errors import ConfigError
from impedance_mil.plant.parameters import ALTERNATIVES, FIELDS, TableParameters
from impedance_mil.specimens import specimen_from_config
from impedance_mil.specimens.factory import VESSEL_FIELDS
from impedance_mil.virtual import presets
from impedance_mil.virtual.files import UNITS as VS_UNITS
from impedance_mil.virtual.files import resolve
from impedance_mil.virtual.registry import BUILTIN

TWO_PI = 2.0 * math.pi
RTOL = 1e-12  # one unit conversion: a few ulps

#: VS keys that only the property listing uses (derived values, never parsed from a file).
# Keys that appear in listings only: the article mass and every type's derived values (computed from
# the parameters, never set; a design file that carries a stale one is refused).
VS_LISTING_ONLY = {"m_ps"} | {x.name for t in BUILTIN.values() for x in t.definition.derived}


def same_value_in(unit: str, value: float) -> list[str]:
    """``value`` (internal unit ``unit``) written in other units that mean the same."""
    if unit == "dimensionless":
        return [f"{100.0 * value!r} percent", f"{100.0 * value!r} %"]
    if unit == "hertz":
        return [f"{TWO_PI * value!r} rad/s", f"{60.0 * value!r} rpm"]
    return []


def misread_values(unit: str) -> list[str]:
    """Values of the wrong dimension for a key in ``unit``: each must be refused naming the key."""
    if unit == "dimensionless":
        return ["5 deg", "1 rad"]  # an angle is not a ratio
    if unit == "hertz":
        return ["50 percent", "3 rad"]
    if unit == "1 / second":  # a rate, not a frequency: 2 rad/s is 2 1/s here, so only angles are wrong
        return ["50 percent", "3 rad"]
    return ["50 percent", "500 percent", f"2 rad * {unit}"]


def close(a, b) -> bool:
    if isinstance(a, (tuple, list)):
        return all(close(x, y) for x, y in zip(a, b, strict=True))
    return math.isclose(a, b, rel_tol=RTOL, abs_tol=0.0)


# ------------------------------------------------------------------ the audit's three cases
def test_the_audit_cases():
    # 169.6 rad/s / 2 pi = 26.9927 Hz (closed form), not 169.6 Hz.
    assert quantity("f_oil_hz", "169.6 rad/s", "hertz") == pytest.approx(169.6 / TWO_PI, rel=RTOL)
    assert quantity("zeta", "20 percent", "dimensionless") == pytest.approx(0.2, rel=RTOL)
    with pytest.raises(ConfigError, match=r"^Ke: expected a quantity with the dimension of volt / inch"):
        quantity("Ke", "500 percent", "volt / inch")


def test_bare_numbers_and_plain_units_are_unchanged():
    assert quantity("f", "27", "hertz") == 27.0  # a number in a string: the report's unit
    assert quantity("f", "27 Hz", "hertz") == 27.0
    assert quantity("f", "27 1/s", "hertz") == 27.0  # 1/s is read as Hz (cycles per second)
    assert quantity("f", "27 turn/s", "hertz") == pytest.approx(27.0, rel=RTOL)
    assert quantity("T", "500 us", "second") == pytest.approx(5e-4, rel=RTOL)


# ------------------------------------------------------------------ table files and --set
TABLE_KEYS = {k: f.unit for k, f in FIELDS.items()} | {k: f.unit for k, (_, f) in ALTERNATIVES.items()}


def _table_with(key):
    """The report's table, or for a key of the general model (issue 13) a table that has it."""
    report = TableParameters.report_default()
    second = report.with_valve("second-order", valve_frequency_hz=80.0, valve_damping=0.7)
    general = {
        "valve_time_constant": report.with_valve("first-order", valve_time_constant=0.0246),
        "valve_frequency_hz": second,
        "valve_damping": second,
        "platen_damping": report.replace(platen_damping=5.0),
        "coulomb_friction": report.replace(coulomb_friction=8.0),
        "output_gain": report.replace(output_gain=1.25),
        "grounded_stiffness": report.replace(grounded_stiffness=300.0),
    }
    return general.get(key, report)


@pytest.mark.parametrize("key", sorted(TABLE_KEYS))
def test_every_table_key(key):
    report = _table_with(key)
    unit = TABLE_KEYS[key]
    current = getattr(report, key)
    base = {k: v for k, v in report.to_dict().items()}
    if key in ALTERNATIVES:
        base.pop(ALTERNATIVES[key][0])
    for text in same_value_in(unit, current) if not isinstance(current, tuple) else []:
        back = TableParameters.from_mapping({**base, key: text})
        assert close(getattr(back, key), current), (key, text)
        assert close(back.to_dict()["f_oil_hz"], report.f_oil_hz)
    if key == "valve_poles_hz":  # a list key: each element converted by dimension
        back = TableParameters.from_mapping({**base, key: [f"{TWO_PI * f!r} rad/s" for f in current]})
        assert close(back.valve_poles_hz, current)
    for text in misread_values(unit):
        value = [text, text] if key == "valve_poles_hz" else text
        with pytest.raises(ConfigError) as info:
            TableParameters.from_mapping({**base, key: value})
        assert info.value.key == key, (key, text, str(info.value))


def test_table_override_from_the_command_line(imil):
    out = imil("table", "info", "--json", "--set", "f_oil_hz=169.6 rad/s")
    assert out.returncode == 0, out.stderr
    assert '"f_oil_hz": 26.99267834838545' in out.stdout  # 169.6 / (2 pi)
    bad = imil("table", "info", "--set", "Ke=500 percent")
    assert (
        bad.returncode == 2 and bad.stderr.startswith("imil: error: Ke: ") and "Traceback" not in bad.stderr
    )
    assert len(bad.stderr.strip().splitlines()) == 1


# ------------------------------------------------------------------ VS files and --set-vs
def vs_presets_by_key() -> dict[str, str]:
    """One preset that knows each settable VS key (model parameter or design target)."""
    out: dict[str, str] = {}
    for name in presets.names():
        spec = resolve(name)
        keys = set(spec.vs.parameters)
        keys |= {f.name for f in dataclasses.fields(spec.targets)} if spec.targets is not None else set()
        for key in keys:
            out.setdefault(key, name)
    return out


VS_KEYS = vs_presets_by_key()


def test_every_vs_key_is_covered():
    assert set(VS_KEYS) | VS_LISTING_ONLY == set(VS_UNITS)


@pytest.mark.parametrize("key", sorted(VS_KEYS))
def test_every_vs_key(key):
    name = VS_KEYS[key]
    spec = resolve(name)
    model_keys = set(spec.vs.parameters)
    current = getattr(spec.vs if key in model_keys else spec.targets, key)
    unit = VS_UNITS[key]
    for text in same_value_in(unit, current):
        back = resolve(name, {key: text})
        for field in spec.vs.parameters:
            assert close(getattr(back.vs, field), getattr(spec.vs, field)), (key, text, field)
    for text in misread_values(unit):
        with pytest.raises(ConfigError) as info:
            resolve(name, {key: text})
        assert info.value.key == key, (key, text, str(info.value))


@pytest.mark.parametrize("key", sorted(VS_LISTING_ONLY))
def test_vs_listing_keys_convert_by_dimension(key):
    unit = VS_UNITS[key]
    for text in same_value_in(unit, 0.25):
        assert quantity(key, text, unit) == pytest.approx(0.25, rel=RTOL)
    for text in misread_values(unit):
        with pytest.raises(ConfigError, match=f"^{key}: "):
            quantity(key, text, unit)


def test_vs_file_key_in_percent(tmp_path):
    path = tmp_path / "sd.toml"
    path.write_text('kind = "SD"\nf = 0.75\nzeta = "30 percent"\nm_vs = "2000 lb"\n')
    from_percent = resolve(str(path))
    path.write_text('kind = "SD"\nf = 0.75\nzeta = 0.30\nm_vs = "2000 lb"\n')
    assert close(from_percent.vs.c, resolve(str(path)).vs.c)
    path.write_text('kind = "SD"\nf = "4.712 rad/s"\nzeta = 0.3\nm_vs = "50 percent"\n')
    with pytest.raises(ConfigError, match=r"^sd\.toml: m_vs: "):
        resolve(str(path))


# ------------------------------------------------------------------ specimen files
SPECIMEN_KEYS = {
    **{("vessel", k): f.unit for k, f in VESSEL_FIELDS.items()},
    ("rigid_mass", "weight"): "force_pound",
    ("shear_building", "story_weights"): "force_pound",
    ("shear_building", "story_stiffness"): "force_pound / inch",
    ("shear_building", "damping_ratio"): "dimensionless",
    ("shear_building", "base_weight"): "force_pound",
}
SPECIMEN_BASE = {
    "vessel": {"type": "vessel", **{k: f.default for k, f in VESSEL_FIELDS.items()}},
    "rigid_mass": {"type": "rigid_mass", "weight": 3600.0},
    "shear_building": {
        "type": "shear_building",
        "story_weights": [800.0, 600.0],
        "story_stiffness": [2000.0, 1500.0],
        "damping_ratio": 0.02,
        "base_weight": 300.0,
    },
}
SPECIMEN_BASE["vessel"]["impulsive_frequency"] = 80.0  # a frequency key with a non-zero value


@pytest.mark.parametrize("kind, key", sorted(SPECIMEN_KEYS))
def test_every_specimen_key(kind, key):
    unit = SPECIMEN_KEYS[(kind, key)]
    base = SPECIMEN_BASE[kind]
    reference = specimen_from_config(base).to_dict()
    current = base[key]
    values = current if isinstance(current, list) else [current]
    wrap = (lambda texts: texts) if isinstance(current, list) else (lambda texts: texts[0])
    if key == "n_convective_modes":
        # A count: "300 percent" is 3 modes; 2.5 modes is refused rather than truncated to 2.
        assert specimen_from_config({**base, key: "300 percent"}).to_dict() == reference
        with pytest.raises(ConfigError, match="n_convective_modes: expected a whole number"):
            specimen_from_config({**base, key: 2.5})
        return
    for i in range(len(same_value_in(unit, 1.0))):
        texts = [same_value_in(unit, v)[i] for v in values]
        back = specimen_from_config({**base, key: wrap(texts)}).to_dict()
        assert _close_dicts(back, reference), (key, texts)
    for text in misread_values(unit):
        with pytest.raises(ConfigError) as info:
            specimen_from_config({**base, key: wrap([text] * len(values))})
        assert info.value.key == f"specimen.{key}", (key, text, str(info.value))


def _close_dicts(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_close_dicts(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(_close_dicts(x, y) for x, y in zip(a, b))
    if isinstance(a, float):
        return math.isclose(a, b, rel_tol=RTOL, abs_tol=1e-300)
    return a == b


# ------------------------------------------------------------------ campaign parameters
CAMPAIGN_KEYS = sorted(
    {
        (name, p.unit, p.check)
        for kind in KINDS.values()
        for name, p in kind.params.items()
        if p.type == "quantity"
    }
)


@pytest.mark.parametrize("name, unit, check", CAMPAIGN_KEYS)
def test_every_campaign_parameter(name, unit, check):
    param = next(k.params[name] for k in KINDS.values() if name in k.params and k.params[name].unit == unit)
    for text in same_value_in(unit, 0.5):
        assert param.convert(f"base.{name}", text) == pytest.approx(0.5, rel=RTOL)
    for text in misread_values(unit):
        with pytest.raises(ConfigError) as info:
            param.convert(f"base.{name}", text)
        assert info.value.key == f"base.{name}", (name, text, str(info.value))
