"""Motion sources: one FEMA P695 naming, the older spelling still read (signals/sources.py)."""

from __future__ import annotations

import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.signals import builtin_motion
from impedance_mil.signals.sources import FemaRecord, fema_source, parse_fema, scaled_motion


def test_one_fema_name_and_the_old_spelling():
    record = FemaRecord("farfield", 14, "a")
    assert fema_source("farfield", 14, "a") == record.source == "fema:farfield:14a"
    for text in ("fema:farfield:14a", "fema:farfield:14:a", "farfield:14a"):
        assert parse_fema(text) == record


@pytest.mark.parametrize("text", ["fema:farfield:x:a", "fema:farfield", "fema:farfield:14", "fema:a:b:c:d"])
def test_a_malformed_fema_source_names_the_key(text):
    with pytest.raises(ConfigError, match="--motion"):
        parse_fema(text, "--motion")


def test_scaled_motion_compresses_then_scales():
    # Section 8.2: t' = t/2 keeps the accelerations; then the PGA is scaled (Table 8.1, 0.8 g).
    gm = scaled_motion("elcentro", time_scale=2.0, pga_g=0.8)
    seed = builtin_motion("elcentro")
    assert gm.time_step == pytest.approx(seed.time_step / 2.0, rel=1e-12)
    assert gm.pga_g == pytest.approx(0.8, rel=1e-12) and gm.npts == seed.npts
