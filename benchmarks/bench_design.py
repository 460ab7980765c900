"""Solve time of the optimized design per case (issue 15), against the filter design, in one run.

Prints, for LR2, FP2, SD2 at 0.7 m_st and SD2 at 0.3 m_st: wall time of the
optimized design (exchange loop + certificate), the solver's own time, the
exchange rounds, the verdicts and e_I; and the wall time of the 80 Hz filter
design of the same case for the ratio.  Run: ``python benchmarks/bench_design.py [points/decade]``.
"""

from __future__ import annotations

import sys
import time

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.design.optimized import OptimizationSettings, design_optimized
from impedance_mil.plant import TableParameters
from impedance_mil.report_config import report_config
from impedance_mil.virtual.files import resolve

CASES = (("LR2", None), ("FP2", None), ("SD2", 0.7), ("SD2", 0.3))


def main(per_decade: int = 2000) -> None:
    p = TableParameters.report_default()
    fc_hz = report_config().design.fc_hz  # the report's cut-off
    tm = table_model(p)
    settings = OptimizationSettings(check_per_decade=per_decade)
    print(f"dense check grid: {per_decade} points/decade")
    print("case        optimized [s]  solver [s]  rounds  feasible  certified  e_I    filter [s]  ratio")
    for name, ratio in CASES:
        spec = resolve(name, {} if ratio is None else {"m_vs": ratio * p.mass})
        vm = virtual_model(spec.vs, name)
        robust = {}
        if vm.equivalent is not None:
            robust = {f"DF {a:g} in": virtual_model(spec.vs, name, amplitude_in=a) for a in (0.25, 4.0)}
        t0 = time.perf_counter()
        design_controller(tm, vm, fc_hz=fc_hz, emit_warnings=False)
        t_filter = time.perf_counter() - t0
        t0 = time.perf_counter()
        d = design_optimized(p, vm, fc_hz=fc_hz, robust_vs=robust, settings=settings)
        t_opt = time.perf_counter() - t0
        o = d.optimization
        label = name + ("" if ratio is None else f"@{ratio:g}")
        print(
            f"{label:10s}  {t_opt:13.1f}  {o['solver_time_s']:10.2f}  {o['rounds']:6d}  {o['feasible']!s:8s}  "
            f"{o['certified']!s:9s}  {d.constraints[0].performance_error:.3f}  {t_filter:10.2f}  {t_opt / t_filter:6.0f}"
        )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2000)
