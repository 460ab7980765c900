"""Stability of the controlled table coupled with a given article (design/coupled.py), mass study."""

import numpy as np
import scipy.linalg

from impedance_mil.design.coupled import closed_loop_poles, coupled_stability
from impedance_mil.design.feasibility import mass_ratio_study
from impedance_mil.specimens import FluidVessel, RigidMass
from impedance_mil.systems import TransferFunction
from impedance_mil.units import G0

from .conftest import MST, sd_model


def test_rigid_mass_on_an_oscillator_is_lumping():
    # z = s^2/(m s^2 + c s + k) w and w = -m_a z give (m + m_a) s^2 + c s + k = 0 (closed form).
    m, c, k, ma = 5.0, 40.0, 900.0, 1600.0 / G0
    H = TransferFunction([1.0, 0.0, 0.0], [m, c, k])
    p = np.sort_complex(closed_loop_poles(H, RigidMass(1600.0).impedance()))
    np.testing.assert_allclose(p, np.sort_complex(np.roots([m + ma, c, k])), rtol=1e-9)
    assert coupled_stability(H, RigidMass(1600.0).impedance()).stable
    # A negative damper makes it unstable.
    assert not coupled_stability(TransferFunction([1.0, 0.0, 0.0], [m, -c, k]), -ma).stable


def _ss_poles(H, Z):
    """Independent route: eigenvalues of the state-space interconnection."""
    A1, B1, C1, D1 = H.to_ss()
    A2, B2, C2, D2 = Z.to_ss()
    E = 1.0 / (1.0 - D1[0, 0] * D2[0, 0])
    Cz = E * np.hstack([C1, D1 @ C2])
    Cw = np.hstack([np.zeros_like(C1), C2]) + D2 @ Cz
    return np.linalg.eigvals(scipy.linalg.block_diag(A1, A2) + np.vstack([B1 @ Cw, B2 @ Cz]))


def test_tf_algebra_poles_match_state_space(table):
    # SD2 controlled table at 80 Hz with the vessel at 36 in: the polynomial route and the
    # state-space route agree on every pole to 1e-6 relative (|p| up to ~6000 rad/s).
    from impedance_mil.design import controlled_table, design_controller

    vs = sd_model(m_vs=1.25 * MST)
    d = design_controller(table, vs, fc_hz=80.0, emit_warnings=False)
    H_c = controlled_table(table, vs, d.H_uz, d.H_uw, "standardized").H_c
    Z = FluidVessel(36).impedance()
    a = np.sort_complex(closed_loop_poles(H_c, Z))
    b = np.sort_complex(_ss_poles(H_c, Z))
    assert a.size == b.size
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-6)


def test_mass_study_passivity_versus_coupled_stability(table):
    # Section 9.4.5: at fc = 80 Hz the experiments ran down to 0.8 m_st and went unstable at 0.7 m_st.
    # Passivity (robust, any passive article) holds at 1.25 m_st and fails from 0.9 m_st down; the
    # nominal linear model coupled with the vessel stays stable even at 0.4 m_st, so the experimental
    # threshold lies between the two (docs/design.md, "Basemat-mass study").
    specimens = {f"vessel {d} in": FluidVessel(d).impedance() for d in (0, 18, 30, 42)}
    cases = mass_ratio_study(
        table,
        lambda m: sd_model(m_vs=m),
        [1.25, 0.9, 0.7, 0.4],
        [80.0],
        design_fc_hz=80.0,
        specimens=specimens,
    )
    passive = [c.at_design_fc.III for c in cases]
    assert passive == [True, False, False, False]
    assert cases[2].at_design_fc.passivity_margin_deg < -10.0  # 0.7 m_st: far from passive
    for c in cases:
        assert [x.specimen for x in c.coupled] == list(specimens)
        assert all(x.stable for x in c.coupled)
    doc = cases[2].to_dict()
    assert doc["passive_at_design_fc"] is False and len(doc["coupled"]) == 4
