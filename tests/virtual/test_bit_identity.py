"""The kernels derived from the SD, LR and FP definitions reproduce the hand-written ones bit for bit.

Reference: ``tests/data/vs_handwritten_kernels_dc9ba1a.npz``, recorded from the
hand-written numba kernels of commit dc9ba1a (tests/data/PROVENANCE.md): simulation
histories, linear-part coefficients, describing-function points, equivalent
linearization, and the MIL runtime's VS (its z_vs does not depend on the controller
for a given w).

Two of the recorded quantities go through numpy/scipy routines whose round-off
changes between library versions: ``scipy.signal.ss2tf`` (the recorded conversion
of the linear part) and the first Fourier coefficient of the describing function
(``np.mean`` of ``force * exp(-j phase)``, whose summation numpy may reorder).
They were identical with the libraries of the recording; with scipy 1.17.1 and numpy 2.4.6 (a fresh
install on 2026-12-04) they differ by 1.8e-16 and 1.3e-15 relative, so they are
compared to :data:`LIBRARY_RTOL`.  The simulation histories and the runtime's VS,
the kernels themselves, stay bit for bit.

The linear-part coefficients were recorded through the conversion of that
commit (``scipy.signal.ss2tf``); the toolkit now converts with
:func:`impedance_mil.ss2tf.ss_to_tf` (issue 11 item 3), whose round-off differs.
So the definition's linear matrices are checked bit for bit through the
recorded conversion, and ``linear_part()`` against the same arrays to round-off.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.signal

from impedance_mil.design import design_controller, table_model
from impedance_mil.design.linearize import equivalent_linearization, harmonic_cycle
from impedance_mil.implement.export import controller_from_design
from impedance_mil.implement.runtime import MILRuntime
from impedance_mil.plant import TableParameters
from impedance_mil.systems import TransferFunction
from impedance_mil.virtual import presets
from impedance_mil.virtual.structure import linear_matrices
from impedance_mil.virtual.system import _drop_residue

#: Relative tolerance of the quantities computed through library routines whose round-off
#: depends on the numpy/scipy version (16 ulp; measured 1.8e-16 and 1.3e-15, see above).
LIBRARY_RTOL = 4e-15

DATA = np.load(Path(__file__).resolve().parents[1] / "data" / "vs_handwritten_kernels_dc9ba1a.npz")


def _inputs():
    rng = np.random.default_rng(12345)
    n, dt = 400, 0.0005
    t = np.arange(n) * dt
    a_g = 386.0886 * (0.5 * np.sin(2 * np.pi * 1.3 * t) + 0.2 * rng.standard_normal(n))
    w = 300.0 * np.sin(2 * np.pi * 0.7 * t) + 50.0 * rng.standard_normal(n)
    return a_g, w, dt


@pytest.mark.parametrize("name", ["SD2", "LR2", "FP2"])
def test_simulation_and_linear_part_are_bit_identical(name):
    a_g, w, dt = _inputs()
    vs = presets.get(name)
    r = vs.simulate(a_g, w, dt)
    for key in ("z_vs", "displacement", "velocity", "force", "f_h", "final_state"):
        np.testing.assert_array_equal(getattr(r, key), DATA[f"{name}/sim/{key}"], err_msg=key)
    lp = vs.linear_part()
    recorded = _linear_part_as_recorded(vs)
    for key in ("H_zag", "H_zw", "H_zfh"):
        tf = getattr(lp, key)
        assert (tf is None) == (f"{name}/lp/{key}/num" not in DATA.files), key
        if tf is None:
            continue
        for part in ("num", "den"):
            ref = DATA[f"{name}/lp/{key}/{part}"]
            np.testing.assert_allclose(
                np.asarray(getattr(recorded[key], part), float), ref, rtol=LIBRARY_RTOL, atol=0
            )
            # ss_to_tf: same degrees and exact zeros, coefficients within 2e-14 relative
            # (measured 1.0e-14, the damping term of LR2's denominator, where ss_to_tf gives
            # c/m within 1.3e-16 for H_zw and the recorded conversion 1.0e-14).
            got = np.asarray(getattr(tf, part), float)
            assert got.shape == ref.shape, (key, part)
            np.testing.assert_array_equal(got == 0.0, ref == 0.0)
            np.testing.assert_allclose(got, ref, rtol=2e-14, atol=0)


def _linear_part_as_recorded(vs):
    """The linear part through the conversion the reference was recorded with (commit dc9ba1a).

    ``scipy.signal.ss2tf``, leading numerator terms below 1e-10 on the spectral
    radius dropped (``TransferFunction.from_ss`` then), residue and minreal as now.
    """
    A, B, C, D = linear_matrices(vs.definition, {**vs.parameters, **vs.derived()})
    omega = max(float(np.max(np.abs(np.linalg.eigvals(A)))), 1e-12)
    out = {}
    for j, key in enumerate(("H_zag", "H_zw", "H_zfh")[: B.shape[1]]):
        num, den = scipy.signal.ss2tf(A, B[:, [j]], C.reshape(1, -1), np.reshape(D[j], (1, 1)))
        num = np.trim_zeros(num[0], "f")
        terms = np.abs(num) * omega ** np.arange(num.size - 1, -1, -1.0)
        num = num[np.nonzero(terms > 1e-10 * terms.max())[0][0] :]
        out[key] = _drop_residue(TransferFunction(num, den), omega).minreal()
    return out


@pytest.mark.parametrize("name", ["LR2", "FP2"])
def test_describing_function_matches_the_recording(name):
    vs = presets.get(name)
    for amp in (0.3, 1.0, 3.0):
        got = np.array([harmonic_cycle(vs, amp, f).stiffness for f in (0.1, 1.0, 10.0)])
        np.testing.assert_allclose(got, DATA[f"{name}/df/{amp}"], rtol=LIBRARY_RTOL, atol=0)
    eq = equivalent_linearization(vs, 1.0)
    np.testing.assert_allclose(eq.stiffness_grid, DATA[f"{name}/eq/grid"], rtol=LIBRARY_RTOL, atol=0)
    np.testing.assert_allclose(
        np.array([eq.effective_hz, eq.k_eff, eq.beta_eff, eq.c_eq]),
        DATA[f"{name}/eq/scalars"],
        rtol=LIBRARY_RTOL,
        atol=0,
    )


@pytest.mark.parametrize("name", ["SD2", "LR2", "FP2"])
def test_runtime_vs_is_bit_identical_in_double_precision(name):
    a_g, w, _ = _inputs()
    design = design_controller(
        table_model(TableParameters.report_default()), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    rt = MILRuntime(controller_from_design(design), vs=presets.get(name), precision="double")
    tr = rt.run_mil(a_g, w)
    np.testing.assert_array_equal(np.asarray(tr.z_vs), DATA[f"{name}/mil/double/z_vs"])
    np.testing.assert_array_equal(np.asarray(rt.x_vs), DATA[f"{name}/mil/double/x_vs"])
