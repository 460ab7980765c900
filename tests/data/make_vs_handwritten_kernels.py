"""Record outputs of the hand-written VS kernels (commit dc9ba1a) for the bit-identity check.

Kept for provenance (tests/data/PROVENANCE.md): it ran on the commit before the VS
definitions; the test regenerates ``a_g`` and ``w`` with the same seed and formula.
"""

import sys

import numpy as np

from impedance_mil.design import design_controller, table_model
from impedance_mil.design.linearize import equivalent_linearization, harmonic_cycle
from impedance_mil.implement.export import controller_from_design
from impedance_mil.implement.runtime import MILRuntime
from impedance_mil.plant import TableParameters
from impedance_mil.virtual import presets

rng = np.random.default_rng(12345)
n = 400
dt = 0.0005
t = np.arange(n) * dt
# a broadband input that drives the hysteresis through several loops
a_g = 386.0886 * (0.5 * np.sin(2 * np.pi * 1.3 * t) + 0.2 * rng.standard_normal(n))
w = 300.0 * np.sin(2 * np.pi * 0.7 * t) + 50.0 * rng.standard_normal(n)
out = {}
design = design_controller(
    table_model(TableParameters.report_default()), form="standardized", fc_hz=80.0, emit_warnings=False
)
ctrl = controller_from_design(design)
for name in ("SD2", "LR2", "FP2"):
    vs = presets.get(name)
    r = vs.simulate(a_g, w, dt)
    for k in ("z_vs", "displacement", "velocity", "force", "f_h", "final_state"):
        out[f"{name}/sim/{k}"] = getattr(r, k)
    lp = vs.linear_part()
    for k in ("H_zag", "H_zw", "H_zfh"):
        tf = getattr(lp, k)
        if tf is not None:
            out[f"{name}/lp/{k}/num"] = np.asarray(tf.num, float)
            out[f"{name}/lp/{k}/den"] = np.asarray(tf.den, float)
    if lp.H_zfh is not None:
        for amp in (0.3, 1.0, 3.0):
            out[f"{name}/df/{amp}"] = np.array(
                [harmonic_cycle(vs, amp, f).stiffness for f in (0.1, 1.0, 10.0)]
            )
        eq = equivalent_linearization(vs, 1.0)
        out[f"{name}/eq/grid"] = eq.stiffness_grid
        out[f"{name}/eq/scalars"] = np.array([eq.effective_hz, eq.k_eff, eq.beta_eff, eq.c_eq])
    for prec in ("double",):
        rt = MILRuntime(ctrl, vs=vs, precision=prec)
        tr = rt.run_mil(a_g, w)
        out[f"{name}/mil/{prec}/u"] = np.asarray(tr.u)
        out[f"{name}/mil/{prec}/z_vs"] = np.asarray(tr.z_vs)
        out[f"{name}/mil/{prec}/x_vs"] = np.asarray(rt.x_vs)
    out[f"{name}/params"] = vs.parameter_array()
np.savez_compressed(sys.argv[1], **out)
print(len(out), "arrays")
