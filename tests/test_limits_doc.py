"""docs/limits.md lists every bound and plausibility rule with the values the code uses."""

from __future__ import annotations

from pathlib import Path

import pytest

from impedance_mil import bounds, config
from impedance_mil.plausibility import SPECIMEN_BOUNDS, TABLE_BOUNDS, VS_ANY_BOUND, VS_BOUNDS

DOC = (Path(__file__).resolve().parent.parent / "docs" / "limits.md").read_text(encoding="utf-8")


def _fmt(value):
    return "—" if value is None else f"{value:g}"


@pytest.mark.parametrize("key", sorted(TABLE_BOUNDS))
def test_every_table_bound_is_documented_with_its_values(key):
    b = TABLE_BOUNDS[key]
    row = f"| `{key}` | {b.unit} | {_fmt(b.error_low)} | {_fmt(b.warn_low)} | {_fmt(b.warn_high)} | {_fmt(b.error_high)} | {b.reason} |"
    assert row in DOC


@pytest.mark.parametrize("unit", [*sorted(VS_BOUNDS), None])
def test_every_vs_bound_is_documented_with_its_values(unit):
    b = VS_BOUNDS[unit] if unit is not None else VS_ANY_BOUND
    first = f"`{unit}`" if unit is not None else "any other unit"
    row = f"| {first} | {b.unit} | {_fmt(b.error_low)} | {_fmt(b.error_high)} | {b.reason} |"
    assert row in DOC


@pytest.mark.parametrize("key", sorted(SPECIMEN_BOUNDS))
def test_every_specimen_bound_is_documented_with_its_values(key):
    b = SPECIMEN_BOUNDS[key]
    row = f"| `{key}` | {b.unit} | {_fmt(b.error_low)} | {_fmt(b.warn_low)} | {_fmt(b.warn_high)} | {_fmt(b.error_high)} | {b.reason} |"
    assert row in DOC


@pytest.mark.parametrize(
    "name, shown",
    [
        ("MAX_RECORD_SAMPLES", f"{bounds.MAX_RECORD_SAMPLES} samples"),
        ("MAX_MOTION_FILE_BYTES", f"{bounds.MAX_MOTION_FILE_BYTES >> 20} MiB"),
        ("MAX_RECORDING_FILE_BYTES", f"{bounds.MAX_RECORDING_FILE_BYTES >> 20} MiB"),
        ("MAX_SPECTRUM_PERIODS", f"{bounds.MAX_SPECTRUM_PERIODS} periods"),
        ("MAX_SPECTRUM_STEPS", f"{bounds.MAX_SPECTRUM_STEPS} periods x samples"),
        ("MAX_MULTISINE_ITERATIONS", f"| {bounds.MAX_MULTISINE_ITERATIONS} |"),
        ("MAX_GRID_PER_DECADE", f"| {bounds.MAX_GRID_PER_DECADE} points per decade |"),
        ("MAX_TOML_BYTES", f"({config.MAX_TOML_BYTES} bytes)"),
        ("MAX_TOML_DEPTH", f"{config.MAX_TOML_DEPTH} levels"),
        ("MAX_NUMBER_DIGITS", f"{config.MAX_NUMBER_DIGITS} digits"),
        ("MAX_QUANTITY_CHARS", f"{config.MAX_QUANTITY_CHARS} characters"),
    ],
)
def test_every_work_bound_is_documented_with_its_value(name, shown):
    line = next(ln for ln in DOC.splitlines() if f"`{name}`" in ln)
    assert shown in line
