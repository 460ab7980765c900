"""Mounting dynamics: a flexible platen mode and the load cells (issue 17, item 1; specimens.mounting).

References: natural frequencies against closed forms (a base-excited
oscillator, two bodies on a spring: omega^2 = k (m1 + m2) / (m1 m2)) and
against an independent generalized eigenproblem (M, K of the lumped
masses); the lab's linearization against the Jacobian of its own compiled
derivative with the table's rigid body reduced to m_st - m_p (the other
form of the same physics); DC gains against the carried masses; a very
stiff mounting against the lab without one (measured figures in each test).
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg

from impedance_mil.errors import ConfigError
from impedance_mil.lab import ideal_sensors, simulate
from impedance_mil.lab.choices import Choices, tracking_test
from impedance_mil.lab.kernels import SPEC_BANK, SPEC_CSR, coupled_derivative
from impedance_mil.lab.labfile import load_lab
from impedance_mil.lab.plant_interface import VirtualTable, specimen_arrays
from impedance_mil.lab.robust import article_impedance, lab_article
from impedance_mil.lab.substeps import choose_substeps, coupled_state_matrix
from impedance_mil.plant import default_table_path
from impedance_mil.plant.nonlinear import N_TABLE_STATES, NonlinearTable
from impedance_mil.specimens import FluidVessel, LinearMDOF, RigidMass
from impedance_mil.specimens.mounting import LoadCells, MountedSpecimen, Mounting, PlatenMode, mount
from impedance_mil.specimens.sensors import SensorSuite
from impedance_mil.units import G0

from .conftest import report_parameters

TABLE = default_table_path()
M_ST = report_parameters().mass  # 4.14 lbf*s^2/in (1600 lb, Table 4.1)


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _free_table_poles(spec: MountedSpecimen, table_mass: float) -> np.ndarray:
    """Poles of the specimen on a free rigid table of mass ``table_mass`` (m z = w, no actuator)."""
    ss = spec.state_space()
    a = ss.A + np.outer(ss.B, ss.C) / (table_mass - ss.D)
    return np.linalg.eigvals(a)


def _oscillating(p: np.ndarray) -> np.ndarray:
    """The natural frequencies [rad/s] of the poles with a positive imaginary part, ascending."""
    return np.sort(np.abs(p[p.imag > 1e-6]))


# ------------------------------------------------------------- (a) natural frequencies
def test_platen_mode_alone_is_f_p_on_a_fixed_base_and_two_bodies_on_a_free_table():
    # Fixed base (z = 0): the poles of A are the mode's, -zeta w +- i w sqrt(1 - zeta^2).
    m_p, f_p, zeta = 0.1 * M_ST, 150.0, 0.03
    spec = mount(None, Mounting(PlatenMode(m_p, f_p, zeta)), M_ST)
    w = 2 * math.pi * f_p
    (pole,) = spec.state_space().poles()[spec.state_space().poles().imag > 0]
    assert abs(pole) == pytest.approx(w, rel=1e-12)
    assert -pole.real / abs(pole) == pytest.approx(zeta, rel=1e-12)
    # Free table (undamped): the rigid body m_st - m_p and the modal mass m_p on k_p = m_p w^2,
    # two bodies on a spring: omega^2 = k_p (m_r + m_p) / (m_r m_p).
    undamped = mount(None, Mounting(PlatenMode(m_p, f_p, 0.0)), M_ST)
    m_r = M_ST - m_p
    expected = math.sqrt(m_p * w**2 * (m_r + m_p) / (m_r * m_p))
    assert _oscillating(_free_table_poles(undamped, M_ST)) == pytest.approx([expected], rel=1e-10)


def test_rigid_article_on_load_cells_closed_forms():
    # A rigid article M on the cells k, c = 2 zeta sqrt(k M): on a fixed base its mode is
    # sqrt(k / M) with damping ratio zeta; on a free table of mass m_st, undamped,
    # omega^2 = k (m_st + M) / (m_st M).
    M, k, zeta = 1600.0 / G0, 2e6, 0.05
    spec = mount(RigidMass(1600.0), Mounting(load_cells=LoadCells(k, zeta)), M_ST)
    p = spec.state_space().poles()
    (pole,) = p[p.imag > 0]
    assert abs(pole) == pytest.approx(math.sqrt(k / M), rel=1e-12)
    assert -pole.real / abs(pole) == pytest.approx(zeta, rel=1e-12)
    undamped = mount(RigidMass(1600.0), Mounting(load_cells=LoadCells(k, 0.0)), M_ST)
    expected = math.sqrt(k * (M_ST + M) / (M_ST * M))
    assert _oscillating(_free_table_poles(undamped, M_ST)) == pytest.approx([expected], rel=1e-10)
    # a damping coefficient is taken as given: c = 40 lbf*s/in gives zeta = c / (2 sqrt(k M))
    given = mount(RigidMass(1600.0), Mounting(load_cells=LoadCells(k, 40.0, damping_is_ratio=False)), M_ST)
    q = given.state_space().poles()
    assert -q[0].real / abs(q[0]) == pytest.approx(40.0 / (2 * math.sqrt(k * M)), rel=1e-12)


def test_platen_cells_base_plate_and_a_two_storey_article_match_the_lumped_eigenproblem():
    # Independent method: the undamped lumped system on a free table, masses
    # [rigid body m_st - m_p, platen m_p, base plate m_b (+ the article's base mass),
    # storeys], stiffness assembled by hand; its generalized eigenvalues are the
    # squares of the composed model's natural frequencies (the rigid-body 0 dropped).
    m_p, f_p, k, m_b = 0.15 * M_ST, 180.0, 3e6, 0.3
    ms, ks = np.array([1.0, 0.8]), np.array([4000.0, 3000.0])
    article = LinearMDOF(np.diag(ms), np.array([[ks.sum(), -ks[1]], [-ks[1], ks[1]]]), np.zeros((2, 2)))
    spec = mount(article, Mounting(PlatenMode(m_p, f_p, 0.0), LoadCells(k, 0.0, m_b)), M_ST)
    kp = m_p * (2 * math.pi * f_p) ** 2
    mass = np.diag([M_ST - m_p, m_p, m_b, *ms])
    K = np.zeros((5, 5))
    for i, j, kk in ((0, 1, kp), (0, 2, k), (2, 3, ks[0]), (3, 4, ks[1])):
        K[np.ix_([i, j], [i, j])] += kk * np.array([[1, -1], [-1, 1]])
    lam = np.sort(scipy.linalg.eigh(K, mass, eigvals_only=True))
    expected = np.sqrt(lam[1:])
    assert _oscillating(_free_table_poles(spec, M_ST)) == pytest.approx(expected, rel=1e-8)


# ------------------------------------------------------------- (b) linearization
@pytest.mark.parametrize(
    "spec",
    [
        mount(
            FluidVessel.report_default(water_depth_in=36.0),
            Mounting(PlatenMode(0.1 * M_ST, 150.0, 0.03)),
            M_ST,
        ),
        mount(RigidMass(1600.0), Mounting(load_cells=LoadCells(2e6, 0.05, 0.5)), M_ST),
        mount(
            FluidVessel.report_default(water_depth_in=18.0),
            Mounting(PlatenMode(0.2 * M_ST, 120.0, 0.02), LoadCells(1e6, 0.03, 0.2)),
            M_ST,
        ),
    ],
    ids=["vessel-platen", "rigid-cells", "vessel-both"],
)
def test_the_lab_linearizes_to_the_composed_model_on_the_reduced_rigid_body(table, spec):
    # The compiled derivative (table of mass m_st, specimen output w_table + m_p z) against the
    # linear model of the other form: the table's rigid body m_st - m_p (oil column, valve
    # and flow gain unchanged) with the specimen's force on it, w_table.  Central differences,
    # 1e-9 of each column's largest entry (measured <= 2e-16; the two forms' matrices agree
    # to 2e-21 of the largest entry).
    reduced = dataclasses.replace(table, mass=spec.rigid_table_mass)
    a = coupled_state_matrix(reduced, spec.table_force_state_space())
    np.testing.assert_allclose(a, coupled_state_matrix(table, spec), rtol=1e-12, atol=1e-12 * np.abs(a).max())
    arrs = specimen_arrays(spec)
    pa = table.parameter_array()
    n = a.shape[0]
    y0 = np.zeros(n)
    y0[:N_TABLE_STATES] = table.equilibrium_state()
    steps = np.r_[1e-6, 1e-5, 1e-3, 1e-3, 1e-6, 1e-3, np.full(n - N_TABLE_STATES, 1e-6)]
    for j in range(n):
        e = np.zeros(n)
        e[j] = steps[j]
        hi, lo = np.empty(n), np.empty(n)
        coupled_derivative(pa, y0 + e, *arrs, 0.0, hi)
        coupled_derivative(pa, y0 - e, *arrs, 0.0, lo)
        col = (hi - lo) / (2 * steps[j])
        assert np.max(np.abs(a[:, j] - col)) <= 1e-9 * max(np.max(np.abs(col)), 1e-12), j


def test_the_substep_rule_sees_the_mounting_mode(table):
    # A 600 Hz platen mode is the plant's fastest: auto substeps rise above the vessel's alone.
    vessel = FluidVessel.report_default(water_depth_in=36.0)
    plain = choose_substeps(table, vessel)
    mounted = choose_substeps(table, mount(vessel, Mounting(PlatenMode(0.1 * M_ST, 600.0, 0.03)), M_ST))
    assert mounted.fastest_rad_s > 2 * math.pi * 600.0 > plain.fastest_rad_s
    assert mounted.substeps > plain.substeps


# ------------------------------------------------------------- (c) static invariants
def _dc(C, D, ss) -> float:
    return float(D - C @ np.linalg.solve(ss.A, ss.B))


def test_dc_forces_are_the_carried_masses_and_w_lc_is_w_without_a_platen():
    vessel = FluidVessel.report_default(water_depth_in=36.0)
    m_p, m_b = 0.1 * M_ST, 0.4
    both = mount(vessel, Mounting(PlatenMode(m_p, 150.0, 0.03), LoadCells(2e6, 0.05, m_b)), M_ST)
    ss, lc = both.state_space(), both.load_cell
    carried = vessel.total_mass + m_b
    assert both.total_mass == pytest.approx(carried, rel=1e-15)
    # at DC the load cells carry the article and the plate; the rigid body feels the platen too
    assert _dc(lc.C, lc.D, ss) == pytest.approx(-carried, rel=1e-9)
    assert _dc(ss.C, ss.D, both.table_force_state_space()) - m_p == pytest.approx(-(carried + m_p), rel=1e-9)
    assert _dc(ss.C, ss.D, ss) == pytest.approx(
        -carried, rel=1e-9
    )  # the m_st table's view: as without a platen
    # Without a platen mode, the force on the table is the load cells' at every frequency.
    cells = mount(vessel, Mounting(load_cells=LoadCells(2e6, 0.05, m_b)), M_ST)
    assert (
        np.array_equal(cells.state_space().C, cells.load_cell.C)
        and cells.state_space().D == cells.load_cell.D
    )
    # With one, they part above the mode: w = w_LC - m_p q_p'' (at 150 Hz the platen's inertia dominates).
    f = np.array([1.0, 150.0])
    w = ss.system.frequency_response(f)
    wl = np.array(
        [lc.C @ np.linalg.solve(2j * np.pi * fi * np.eye(ss.n_states) - ss.A, ss.B) + lc.D for fi in f]
    )
    assert abs(w[0] / wl[0] - 1) < 1e-3 and abs(w[1] / wl[1] - 1) > 0.5


def test_the_load_cells_read_their_own_output_in_the_lab(table):
    # VirtualTable with ideal sensors: the load-cell reading equals C_lc y + D_lc z of the plant
    # state (the sensing kernel reads the second output), not w.  Measured 5e-12 relative: the
    # reading goes through the channel's volts and back.
    spec = mount(RigidMass(1600.0), Mounting(PlatenMode(0.1 * M_ST, 150.0, 0.03), LoadCells(2e6, 0.05)), M_ST)
    plant = VirtualTable(table, spec, sensors=ideal_sensors(), quantize=False)
    for k in range(200):
        plant.read_sensors()
        plant.write_command(0.05 * math.sin(2 * math.pi * 20 * k * table.loop_time))
        plant.advance()
    m = plant.read_sensors()
    truth = plant.truth()
    ys = plant.y[N_TABLE_STATES:]
    expected = spec.load_cell.C @ ys + spec.load_cell.D * truth["z"]
    assert m.w_lc == pytest.approx(expected, rel=1e-10)
    assert abs(m.w_lc - truth["w"]) > 1e-3 * abs(truth["w"])  # the platen's inertia is between them


# ------------------------------------------------------------- (d) a stiff mounting converges
def _open_loop(table, specimen):
    n = 1000
    t = np.arange(n) * table.loop_time
    u = 0.1 * np.sin(2 * np.pi * 5 * t) + 0.02 * np.sin(2 * np.pi * 23 * t)
    return simulate(table, command=u, specimen=specimen, sensors=ideal_sensors(), quantize=False)


def test_a_stiff_mounting_converges_to_the_lab_without(table):
    # 0.5 s of open-loop command (5 + 23 Hz), 1600 lb rigid article, auto substeps.  Peak
    # error of z relative to its peak, measured: cells k = 1e7, 1e8, 1e9 lbf/in (zeta 5 %;
    # 2, 6, 17 substeps): 1.1e-2, 6.8e-3, 5.8e-4; platen of 0.1 m_st at 2 kHz: 1.6e-4.
    art = RigidMass(1600.0)
    ref = _open_loop(table, art)
    peak = np.max(np.abs(ref.z))
    errors = []
    for k in (1e7, 1e8, 1e9):
        run = _open_loop(table, mount(art, Mounting(load_cells=LoadCells(k, 0.05)), M_ST))
        errors.append(np.max(np.abs(run.z - ref.z)) / peak)
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-3
    platen = _open_loop(table, mount(art, Mounting(PlatenMode(0.1 * M_ST, 2000.0, 0.03)), M_ST))
    assert np.max(np.abs(platen.z - ref.z)) / peak < 3e-4


# ------------------------------------------------------------- (e) the lab file
def _lab(tmp_path, text: str):
    path = tmp_path / "lab.toml"
    path.write_text(
        f'[table]\nfile = "{TABLE}"\n[specimen]\nkind = "rigid"\narticle_weight = "1600 lbf"\n' + text
    )
    return path


GOOD = """
[dynamics.platen]
mass_fraction = "10 %"
frequency = "150 Hz"
damping = "3 %"
[dynamics.load_cells]
stiffness = "2e6 lbf/in"
damping = "5 %"
base_mass = "200 lb"
[dynamics.friction]
pressure_coefficient = "0.002 lbf/psi"
"""


def test_the_lab_file_sets_the_mounting_and_the_runs_and_checks_use_it(tmp_path):
    lab = load_lab(_lab(tmp_path, GOOD))
    m = lab.dynamics.mounting
    assert m.platen == PlatenMode(0.1 * lab.table.mass, 150.0, 0.03)
    assert m.load_cells == LoadCells(2e6, 0.05, 200.0 / G0)  # 200 lb of mass is 200/g0 lbf*s^2/in, exact
    # the table's own sub-table is passed through here and parsed into the table (plant.table_dynamics)
    assert lab.dynamics.others == {"friction": {"pressure_coefficient": "0.002 lbf/psi"}}
    assert lab.table.dynamics.pressure_friction == pytest.approx(0.002)
    assert lab.to_dict()["dynamics"]["load_cells"]["stiffness"] == 2e6
    test = tracking_test(Choices(lab=str(lab.path), duration=1.0))
    assert isinstance(test.specimen.specimen, MountedSpecimen) and "load cells" in test.specimen.label
    article = lab_article(lab)  # what design --robust and the pre-test check couple with
    f = np.array([5.0, 150.0])
    z_check = article_impedance(article)
    np.testing.assert_allclose(
        [complex(z_check(2j * np.pi * fi)) for fi in f],
        mount(RigidMass(1600.0), m, lab.table.mass).state_space().frequency_response(f),
        rtol=1e-6,
    )


@pytest.mark.parametrize(
    "text, key",
    [
        ("[dynamics.plate]\nfrequency = 1\n", "dynamics.plate"),
        ('[dynamics.platen]\nmodal_mass = 0.2\nfrequency = 150\nzeta = "3 %"\n', "dynamics.platen.zeta"),
        ('[dynamics.platen]\nmodal_mass = 0.2\nfrequency = "150 lbf"\n', "dynamics.platen.frequency"),
        ('[dynamics.platen]\nmodal_mass = "2 lbf/in"\nfrequency = 150\n', "dynamics.platen.modal_mass"),
        ("[dynamics.platen]\nmodal_mass = 5.0\nfrequency = 150\n", "dynamics.platen.modal_mass"),
        ("[dynamics.platen]\nmass_fraction = 1.0\nfrequency = 150\n", "dynamics.platen.mass_fraction"),
        (
            "[dynamics.platen]\nmodal_mass = 0.2\nmass_fraction = 0.1\nfrequency = 150\n",
            "dynamics.platen.modal_mass",
        ),
        ("[dynamics.platen]\nmodal_mass = 0.2\nfrequency = 0\n", "dynamics.platen.frequency"),
        ("[dynamics.platen]\nmodal_mass = 0.2\n", "dynamics.platen.frequency"),
        ("[dynamics.platen]\nmodal_mass = 0.2\nfrequency = 150\ndamping = -0.1\n", "dynamics.platen.damping"),
        ("[dynamics.load_cells]\nstiffness = -1\n", "dynamics.load_cells.stiffness"),
        ('[dynamics.load_cells]\nstiffness = "2e6 lbf"\n', "dynamics.load_cells.stiffness"),
        ("[dynamics.load_cells]\ndamping = 0.05\n", "dynamics.load_cells.stiffness"),
        ('[dynamics.load_cells]\nstiffness = 2e6\ndamping = "3 lbf"\n', "dynamics.load_cells.damping"),
        ('[dynamics.load_cells]\nstiffness = 2e6\nbase_mass = "-3 kg"\n', "dynamics.load_cells.base_mass"),
        ("[dynamics.load_cells]\nstiffness = 2e6\nspring = 1\n", "dynamics.load_cells.spring"),
        ("[dynamics]\nplaten = 3\n", "dynamics.platen"),
    ],
)
def test_bad_dynamics_name_the_key(tmp_path, text, key):
    with pytest.raises(ConfigError) as err:
        load_lab(_lab(tmp_path, text))
    assert err.value.key == f"lab.toml: {key}"


def test_lab_check_refuses_in_one_line_with_exit_2(tmp_path):
    path = _lab(tmp_path, "[dynamics.platen]\nmodal_mass = 5.0\nfrequency = 150\n")
    r = subprocess.run(
        [sys.executable, "-m", "impedance_mil", "lab", "check", str(path)], capture_output=True, text=True
    )
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1
    assert lines[0].startswith("imil: error: lab.toml: dynamics.platen.modal_mass: ")


# ------------------------------------------------------------- (f) nothing given, nothing changed
def test_no_mounting_is_the_article_itself_and_the_arrays_are_unchanged(tmp_path):
    vessel = FluidVessel.report_default(water_depth_in=36.0)
    assert mount(vessel, None, M_ST) is vessel and mount(vessel, Mounting(), M_ST) is vessel
    arrs = specimen_arrays(vessel)
    assert arrs.lc_own == 0 and np.array_equal(arrs.C_lc, arrs.C) and arrs.D_lc == arrs.D
    assert load_lab(_lab(tmp_path, "")).dynamics.mounting is None
    assert load_lab(_lab(tmp_path, "[dynamics]\n")).dynamics.mounting is None


def test_a_platen_on_a_bank_keeps_the_fast_path_and_agrees_with_the_general_one(table):
    # Platen only, on a bank of oscillators (the vessel): still a bank (interleaved states);
    # the bank and CSR paths take the same RK4 stages and agree to round-off (as
    # tests/lab/test_oscillator_bank.py: 1e-12 of the peak; measured 3e-14).  Load cells: CSR.
    vessel = FluidVessel.report_default(water_depth_in=36.0)
    spec = mount(vessel, Mounting(PlatenMode(0.1 * M_ST, 150.0, 0.03)), M_ST)
    assert specimen_arrays(spec).kind == SPEC_BANK
    assert specimen_arrays(mount(vessel, Mounting(load_cells=LoadCells(2e6)), M_ST)).kind == SPEC_CSR
    n = 300
    u = 0.1 * np.sin(2 * np.pi * 7 * np.arange(n) * table.loop_time)
    runs = []
    for bank in (True, False):
        plant = VirtualTable(table, spec, sensors=ideal_sensors(), quantize=False)
        if not bank:
            plant.plant = plant.plant._replace(specimen=specimen_arrays(spec, oscillator_bank=False))
        z = []
        for k in range(n):
            z.append(plant.read_sensors().z)
            plant.write_command(u[k])
            plant.advance()
        runs.append(np.array(z))
    assert np.max(np.abs(runs[0] - runs[1])) <= 1e-12 * np.max(np.abs(runs[1]))


def test_a_filtered_load_cell_channel_filters_the_load_cell_force(table):
    # The anti-alias filters advance inside the plant step on the load cells' output when the
    # specimen has its own (lc_own = 1).  Without a platen mode that output equals w: the run
    # with lc_own = 1 must equal the one forced to read w (lc_own = 0) to round-off (measured
    # 0, the same operations), while with a platen mode the two differ (the filter input differs;
    # measured 6.5e-3 of the peak).
    def filtered_readings(spec, own: bool) -> np.ndarray:
        suite = ideal_sensors()
        suite = SensorSuite(
            [
                dataclasses.replace(s, bandwidth_hz=200.0, filter_order=2)
                if s.quantity == "interface_force"
                else s
                for s in suite.sensors
            ]
        )
        plant = VirtualTable(table, spec, sensors=suite, quantize=False, substeps=3)
        if not own:
            plant.plant = plant.plant._replace(specimen=plant.plant.specimen._replace(lc_own=0))
        out = []
        for k in range(200):
            out.append(plant.read_sensors().w_lc)
            plant.write_command(0.05 * math.sin(2 * math.pi * 20 * k * table.loop_time))
            plant.advance()
        return np.array(out)

    cells = mount(RigidMass(1600.0), Mounting(load_cells=LoadCells(2e6, 0.05)), M_ST)
    a, b = filtered_readings(cells, True), filtered_readings(cells, False)
    assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))
    both = mount(RigidMass(1600.0), Mounting(PlatenMode(0.1 * M_ST, 150.0, 0.03), LoadCells(2e6, 0.05)), M_ST)
    c, d = filtered_readings(both, True), filtered_readings(both, False)
    assert np.max(np.abs(c - d)) > 1e-4 * np.max(np.abs(d))


def test_cells_under_an_article_with_no_base_mass_need_a_base_plate():
    # A shear building with no rigid base mass (D = 0) on massless cells: the cells and the first
    # storey would be two springs in series with no mass between them; refused, naming the key.
    article = LinearMDOF(np.eye(1), np.array([[4000.0]]), np.zeros((1, 1)))
    with pytest.raises(ConfigError) as err:
        mount(article, Mounting(load_cells=LoadCells(2e6)), M_ST)
    assert err.value.key == "dynamics.load_cells.base_mass"
    assert mount(
        article, Mounting(load_cells=LoadCells(2e6, base_mass=0.1)), M_ST
    ).total_mass == pytest.approx(1.1)
