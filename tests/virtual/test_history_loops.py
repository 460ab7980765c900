"""The generated loops over input histories (virtual.codegen.HISTORY_LOOPS).

Invariant: ``simulate`` (one compiled loop) equals the type's own kernels called sample by sample
from Python, bit for bit; and the loops are cached, so a second process loads them instead of
compiling them (before, they took the kernels as first-class arguments, could not be cached, and
cost 0.3-0.45 s of every ``imil simulate``).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from impedance_mil.virtual import codegen, presets

ROOT = Path(__file__).resolve().parents[2]


def test_simulate_equals_the_kernels_called_sample_by_sample():
    vs = presets.get("LR2")  # a nonlinear type: its outputs carry the nonlinear input too
    rng = np.random.default_rng(3)
    a_g, w = 200.0 * rng.standard_normal(400), 50.0 * rng.standard_normal(400)
    dt = 0.0005
    got = vs.simulate(a_g, w, dt=dt)
    kern = codegen.compiled(vs.definition)
    x = vs.initial_state().copy()
    out, work = np.empty(kern.n_outputs), np.empty(4 * vs.n_states)
    z, force = np.empty(a_g.size), np.empty(a_g.size)
    states = np.empty((a_g.size, vs.n_states))
    for k in range(a_g.size):
        states[k] = x
        kern.outputs(vs._params, x, a_g[k], w[k], out)
        z[k], force[k] = out[0], out[3]
        kern.tick64(vs._params, x, a_g[k], w[k], dt, work)
    np.testing.assert_array_equal(got.z_vs, z)
    np.testing.assert_array_equal(got.force, force)
    np.testing.assert_array_equal(got.final_state, x)
    # outputs_along: the force of recorded states, as outputs() gives it with a_g = w = 0
    along = np.empty(a_g.size)
    for k in range(a_g.size):
        kern.outputs(vs._params, states[k].copy(), 0.0, 0.0, out)
        along[k] = out[3]
    np.testing.assert_array_equal(vs.force_along(states), along)


PROBE = """
import json
from impedance_mil.virtual import codegen, presets
vs = presets.get("SD2")
vs.simulate([1.0, 2.0, 3.0])
vs.force_along([[0.1, 0.2], [0.3, 0.4]])
kern = codegen.compiled(vs.definition)
print(json.dumps({name: [len(getattr(kern, name).stats.cache_hits), len(getattr(kern, name).stats.cache_misses)]
                  for name in ("simulate_records", "outputs_along")}))
"""


def test_a_second_process_loads_the_loops_from_the_cache(tmp_path):
    env = {
        **os.environ,
        "IMPEDANCE_MIL_CACHE_DIR": str(tmp_path / "vs"),
        "NUMBA_CACHE_DIR": str(tmp_path / "nb"),
    }
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH", "")) if p)

    def probe() -> dict:
        done = subprocess.run(
            [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True
        )
        return json.loads(done.stdout.strip().splitlines()[-1])

    first, second = probe(), probe()
    assert all(misses == 1 for _, misses in first.values()), first  # compiled once, then saved
    assert second == {"simulate_records": [1, 0], "outputs_along": [1, 0]}, second
