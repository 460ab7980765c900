"""Tables from cited public sources (issue 13, "Done when"), read through the toolkit's own reader.

Sources and their printed numbers: ``impedance_mil/data/PROVENANCE.md`` (section ``tables/``)
and the header comment of each file.

* ``lnec_st1d_tekeste_2021.toml``: the LNEC ST1D shake table identified by Tekeste (2021), a
  physical table with a first-order valve (tau_sv = 24.6 ms). Printed result: the oil-column
  term ``K_h = 4 beta_e A^2 / V_t`` = 45213171683 (Henrique 2026, table "ST1D model
  parameters", unit printed "Pa/m"). The toolkit's oil column ``omega_oil^2 m_p`` gives the
  same eleven digits in N/m times 1e-3: the printed number is 1000 times its own formula on its
  own values (the MSc script multiplies by 1e3 after converting beta_e to Pa). No source we
  could read prints the frequency in Hz; the toolkit's, 24.08 Hz, follows from K_h and m_p.
* ``rths_benchmark_plant.toml``: the RTHS benchmark plant as a transfer function (Li,
  ``Actuator_id.m``). Printed result: the DC gain, as ``a = DC*c; % 53529`` with
  ``c = 54516``. Its poles are printed by no source we could read; they are checked against
  the roots of the source's own denominator.
"""

import tomllib
from fractions import Fraction
from importlib import resources

import numpy as np
import pytest

from impedance_mil.plant import LinearTable, plant_state_space
from impedance_mil.plant.lti_table import LTITable
from impedance_mil.plant.parameters import TableParameters
from impedance_mil.plant.table_files import read_table_file
from impedance_mil.units import TWO_PI

TABLES = resources.files("impedance_mil") / "data" / "tables"
LNEC = TABLES / "lnec_st1d_tekeste_2021.toml"
RTHS = TABLES / "rths_benchmark_plant.toml"

# Definitions of the units (exact): the toolkit is in in, lbf; the sources in SI.
M_PER_IN = 0.0254
N_PER_LBF = 4.4482216152605

# Tekeste (2021) as printed (slide 13; Henrique 2026, table "ST1D model parameters"), SI.
TAU_SV = 0.0246  # s
KSV_KQ = 1934.50e-6  # m^3/s/V
K_PL = 1.67401e-10  # m^3/s/Pa
BETA_E = 193716280.0  # Pa
V_T = 0.002659  # m^3
AREA = 0.012456  # m^2
M_P = 1975.1  # kg
C_T = 5780.0  # N s/m
K_P = 129.93  # V/m
K_H_PRINTED = 45213171683.0  # Henrique (2026), printed with the unit "Pa/m"


def lnec() -> TableParameters:
    table = read_table_file(LNEC)
    assert isinstance(table, TableParameters)
    return table


def rths() -> LTITable:
    table = read_table_file(RTHS)
    assert isinstance(table, LTITable)
    return table


def test_lnec_file_holds_the_printed_values():
    # The file's values, in the source's units, arrive in the toolkit's units unchanged
    # (converted back to SI within 1e-12; measured 3e-16).
    p = lnec()
    assert p.valve == "first-order" and p.valve_time_constant == pytest.approx(TAU_SV, rel=1e-15)
    got = {
        "A [m^2]": p.piston_area * M_PER_IN**2,
        "V_t [m^3]": 2.0 * p.piston_area * p.mid_stroke * M_PER_IN**3,
        "m_p [kg]": p.mass * N_PER_LBF / M_PER_IN,
        "c_t [N s/m]": p.platen_damping * N_PER_LBF / M_PER_IN,
        "k_p [V/m]": p.Ke / M_PER_IN,
        "beta_e [Pa]": p.bulk_modulus * N_PER_LBF / M_PER_IN**2,
        "k_pl [m^3/s/Pa]": p.leakage_coefficient * M_PER_IN**5 / N_PER_LBF,
    }
    want = {
        "A [m^2]": AREA,
        "V_t [m^3]": V_T,
        "m_p [kg]": M_P,
        "c_t [N s/m]": C_T,
        "k_p [V/m]": K_P,
        "beta_e [Pa]": BETA_E,
        "k_pl [m^3/s/Pa]": K_PL,
    }
    for key, value in want.items():
        assert got[key] == pytest.approx(value, rel=1e-12), key


def test_lnec_oil_column_reproduces_the_printed_K_h():
    # Printed K_h = 45213171683 ("Pa/m"), eleven digits. The toolkit's oil column from the
    # bulk modulus (Eq 4-10a with x_m = V_t / 2A): omega_oil^2 m_p = 4 beta_e A^2 / V_t =
    # 4.5213171683667e7 N/m, the printed digits (truncated, not rounded: 1.5e-11) times 1e-3.
    # Tolerance 1e-10 on the eleven printed digits.
    p = lnec()
    k_h = p.omega_oil**2 * p.mass * N_PER_LBF / M_PER_IN  # N/m
    assert 1e3 * k_h == pytest.approx(K_H_PRINTED, rel=1e-10)
    # The frequency no source prints: sqrt(K_h / m_p) / 2 pi, K_h read as 1e-3 of the print.
    f_from_print = np.sqrt(K_H_PRINTED * 1e-3 / M_P) / TWO_PI
    assert p.f_oil_hz == pytest.approx(f_from_print, rel=1e-10)
    assert p.f_oil_hz == pytest.approx(24.080, abs=5e-4)


def test_lnec_closed_loop_is_the_sources_transfer_function():
    # The source's closed loop x_T/x_ref with the platen alone (m_T = m_p; Henrique's
    # Eq eq_G_Fp_isv closed by k_p, written out in parameters_transFunc.m, commit 6a9bc86):
    #   K / (K + s (tau_sv s + 1)(A^2 m_p s^2 + (A^2 c_t + k_pl k_h m_p) s + A^2 k_h + k_pl c_t k_h))
    # with K = A k_h k_p k_sv k_q and k_h = 4 beta_e A^2 / V_t. The toolkit's x/u (delay none)
    # equals it within 1e-12 from 0.1 to 100 Hz (measured 2e-15).
    f = np.geomspace(0.1, 100.0, 80)
    s = 1j * TWO_PI * f
    k_h = 4.0 * BETA_E * AREA**2 / V_T
    gain = AREA * k_h * K_P * KSV_KQ
    hydraulic = (
        AREA**2 * M_P * s**2 + (AREA**2 * C_T + K_PL * k_h * M_P) * s + AREA**2 * k_h + K_PL * C_T * k_h
    )
    source = gain / (gain + s * (TAU_SV * s + 1.0) * hydraulic)
    got = LinearTable(lnec(), delay="none").state_space().frequency_response("x", "u", f)
    np.testing.assert_allclose(got, source, rtol=1e-12)


def test_lnec_open_loop_valve_pole_is_minus_one_over_tau_sv():
    # The valve of the open-loop plant (Eq 4-11 with the first-order valve): one real pole at
    # -1/tau_sv = -40.65 rad/s (1e-12; it is the diagonal entry of a triangular block).
    poles = plant_state_space(lnec()).poles()
    assert np.min(np.abs(poles + 1.0 / TAU_SV)) == pytest.approx(0.0, abs=1e-12 / TAU_SV)


# Li, Actuator_id.m, line 1 (the benchmark's parameters, as printed there).
SOURCE = {
    "a1": "2.13e13",
    "a2": "4.23e6",
    "me": "29.1",
    "ce": "114.6",
    "a3": "3.3",
    "b1": "425",
    "b2": "10e4",
    "ke": "1.19e6",
}


def source_polynomials() -> tuple[Fraction, list[Fraction]]:
    """``a1`` and ``[me, A4, A3, A2, A1, A0]`` by the formulas of Actuator_id.m, exactly."""
    v = {k: Fraction(x) for k, x in SOURCE.items()}
    t3 = v["ce"] + v["me"] * v["a3"]
    t1 = v["ke"] * v["a3"]
    t2 = v["ke"] + v["ce"] * v["a3"] + v["a2"]
    den = [
        v["me"],
        t3 + v["me"] * v["b1"],
        t2 + t3 * v["b1"] + v["me"] * v["b2"],
        t1 + t2 * v["b1"] + t3 * v["b2"],
        t1 * v["b1"] + t2 * v["b2"],
        t1 * v["b2"] + v["a1"],
    ]
    return v["a1"], den


def test_rths_file_is_the_sources_polynomial():
    # Every coefficient of the file is the source's formula on its printed values, to the bit
    # (the products of short decimals are short decimals), and z/u = s^2 x/u.
    a1, den = source_polynomials()
    model = tomllib.loads(RTHS.read_text())["model"]
    assert model["H_zu"]["num"] == [float(a1), 0.0, 0.0]
    assert model["H_zu"]["den"] == [float(c) for c in den]
    assert "H_zw" not in model and rths().has_force_path() is False


def test_rths_dc_gain_reproduces_the_printed_value():
    # Printed: "a = DC*c; % 53529" with c = 54516 (five digits each): DC = 0.981895 +- 1.9e-5
    # relative. Measured: 0.9818971 (1.9e-6 from 53529/54516; DC * 54516 = 53529.10).
    dc = rths().dcgain("x", "u")
    assert round(dc * 54516) == 53529
    assert dc == pytest.approx(53529 / 54516, rel=2e-5)
    a1, den = source_polynomials()
    assert dc == pytest.approx(float(a1 / den[-1]), rel=1e-12)  # a1/A0, the closed form


def test_rths_poles_are_the_roots_of_the_sources_denominator():
    # Not printed by the sources we read; the toolkit's five poles (realized from the file) equal
    # the roots of me s^5 + ... + A0 within 1e-9 (measured: identical): 7.68 Hz real, 46.87 Hz
    # (zeta 0.625) and 67.18 Hz (zeta 0.019).
    _, den = source_polynomials()
    want = np.sort_complex(np.roots([float(c) for c in den]))
    got = np.sort_complex(rths().poles())
    np.testing.assert_allclose(got, want, rtol=1e-9)
    assert sorted({round(abs(p) / TWO_PI, 2) for p in got}) == [7.68, 46.87, 67.18]
