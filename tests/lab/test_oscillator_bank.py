"""The oscillator-bank path of the plant step equals the general compressed-row path."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.lab.kernels import SPEC_BANK, SPEC_CSR, plant_advance
from impedance_mil.lab.plant_interface import specimen_arrays
from impedance_mil.lab.structures import FilterArrays
from impedance_mil.lab.substeps import resolve_substeps
from impedance_mil.plant.nonlinear import N_TABLE_STATES, NonlinearTable
from impedance_mil.specimens import FluidVessel, LinearMDOF, RigidMass

from .conftest import report_parameters

N_TICKS = 4000  # 2 s of 500 us loops: several periods of the 0.9 Hz sloshing mode

#: The bare plant step: no sensor filters.
NO_FILTERS = FilterArrays.none()


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _trajectory(table, specimen, arrays):
    """Plant state after every tick under a two-tone valve current (30 % of the valve's range)."""
    nsub = resolve_substeps("auto", table, specimen)[0]
    n = N_TABLE_STATES + arrays[3].size
    y = np.zeros(n)
    y[:N_TABLE_STATES] = table.equilibrium_state()
    work = np.zeros((5, n))
    amp = 0.3 * table.Kv * table.valve_command_limit
    t = np.arange(N_TICKS) * table.loop_time
    current = amp * (0.7 * np.sin(2 * np.pi * 2.0 * t) + 0.3 * np.sin(2 * np.pi * 23.0 * t))
    out = np.empty((N_TICKS, n))
    for k in range(N_TICKS):
        plant_advance(
            table.parameter_array(), y, *arrays, current[k], table.loop_time, nsub, work, NO_FILTERS
        )
        out[k] = y
    return out


@pytest.mark.parametrize(
    "specimen",
    [FluidVessel.report_default(water_depth_in=d) for d in (0.0, 18.0, 36.0, 42.0)] + [RigidMass(1600.0)],
    ids=["vessel-0", "vessel-18", "vessel-36", "vessel-42", "rigid"],
)
def test_bank_path_equals_the_general_path(table, specimen):
    # Independent method: the same RK4 stages through the general compressed-row
    # state space (oscillator_bank=False).  The stage derivatives are computed with
    # the same operations; only the force sum C x is taken in another order, so
    # every state agrees to round-off: 1e-9 of the state's peak over the run.
    bank = specimen_arrays(specimen)
    csr = specimen_arrays(specimen, oscillator_bank=False)
    assert bank[6] == SPEC_BANK and csr[6] == SPEC_CSR
    a, b = _trajectory(table, specimen, bank), _trajectory(table, specimen, csr)
    assert np.all(np.isfinite(b))
    peak = np.max(np.abs(b), axis=0)
    assert np.all(np.abs(a - b) <= 1e-9 * np.maximum(peak, 1e-300))


def test_vessel_bank_coefficients_are_its_oscillators():
    # Definition: osc_k = -omega^2, osc_c = -2 zeta omega of vessel.oscillators()
    # (rad/s from Hz; 1e-12 relative, round-off of the mass-normalized matrices).
    vessel = FluidVessel.report_default(water_depth_in=36.0)
    arrays = specimen_arrays(vessel)
    osc = vessel.oscillators()
    omega = 2 * np.pi * np.array([o.frequency_hz for o in osc])
    zeta = np.array([o.damping_ratio for o in osc])
    np.testing.assert_allclose(arrays[7], -(omega**2), rtol=1e-12)
    np.testing.assert_allclose(arrays[8], -2 * zeta * omega, rtol=1e-12)


def test_coupled_mdof_keeps_the_general_path():
    # A two-story shear building couples its DOFs (off-diagonal stiffness): not a bank.
    building = LinearMDOF.shear_building([2000.0, 1000.0], [500.0, 400.0], 0.02)
    assert specimen_arrays(building)[6] == SPEC_CSR
