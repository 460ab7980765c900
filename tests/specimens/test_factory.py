"""Specimens from configuration tables (units at the edge) and from to_dict (round trip)."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.specimens import (
    FluidVessel,
    LinearMDOF,
    RigidMass,
    specimen_from_config,
    specimen_from_dict,
)


def test_vessel_from_config_with_units():
    spec = specimen_from_config(
        {"type": "vessel", "water_depth": "0.9144 m", "dry_weight": "1.2 kip", "impulsive_frequency": "80 Hz"}
    )
    assert isinstance(spec, FluidVessel)
    assert spec.water_depth_in == pytest.approx(36.0, rel=1e-12)  # 0.9144 m = 36 in exactly
    assert spec.dry_weight_lbf == pytest.approx(1200.0, rel=1e-12)
    assert spec.flexible_impulsive_mode().frequency_hz == pytest.approx(80.0)
    default = specimen_from_config({"type": "vessel"})
    assert default == FluidVessel.report_default()
    assert specimen_from_config({"water_depth": 36.0}) == default  # type defaults to vessel


def test_rigid_mass_and_shear_building_from_config():
    rigid = specimen_from_config({"type": "rigid_mass", "weight": "3.6 kip"})
    assert rigid == RigidMass(3600.0)
    building = specimen_from_config(
        {
            "type": "shear_building",
            "story_weights": [800, "600 lbf"],
            "story_stiffness": ["2 kip/in", 1500.0],
            "damping_ratio": 0.03,
        }
    )
    assert isinstance(building, LinearMDOF)
    assert building.total_weight == pytest.approx(1400.0, rel=1e-12)
    np.testing.assert_allclose(building.modes().damping_ratios, 0.03, rtol=1e-10)
    assert building.stiffness[0, 0] == pytest.approx(3500.0)


@pytest.mark.parametrize(
    "cfg, key",
    [
        ({"type": "tank"}, "specimen.type"),
        ({"water_depth": "3 kip"}, "specimen.water_depth"),
        ({"depth": 3.0}, "specimen.depth"),
        ({"type": "rigid_mass"}, "specimen.weight"),
        ({"type": "shear_building", "story_weights": [1.0]}, "specimen.story_stiffness"),
    ],
)
def test_bad_config_names_the_key(cfg, key):
    with pytest.raises(ConfigError) as info:
        specimen_from_config(cfg)
    assert info.value.key == key


@pytest.mark.parametrize(
    "spec",
    [
        RigidMass(1234.0),
        FluidVessel(18.0, n_convective_modes=2),
        LinearMDOF.shear_building([500.0, 400.0], [900.0, 700.0], 0.04, 100.0),
    ],
    ids=lambda s: type(s).__name__,
)
def test_to_dict_round_trip(spec):
    back = specimen_from_dict(spec.to_dict())
    f = np.logspace(-1, 3, 50)
    np.testing.assert_allclose(
        back.state_space().frequency_response(f), spec.state_space().frequency_response(f), rtol=1e-12
    )
    with pytest.raises(ConfigError):
        specimen_from_dict({"type": "Elephant"})
