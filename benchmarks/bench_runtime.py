"""Timing of the MIL controller step: generated C (ns/step) and Python runtime (us/step).

Prints the fraction of the report's 500 us loop that one C step uses (goal:
well under 1 %).  Controller: the report's standardized controller (Table 4.1
table, 3rd-order Butterworth at 80 Hz), MIL step with the SD2 virtual system.
Run: .venv/bin/python benchmarks/bench_runtime.py
"""

from __future__ import annotations

import ctypes
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from impedance_mil.design import design_controller, table_model
from impedance_mil.implement import MILRuntime
from impedance_mil.implement.c import render_c
from impedance_mil.implement.export import controller_from_design
from impedance_mil.implement.safety import HOLD, command_limits
from impedance_mil.plant import TableParameters
from impedance_mil.virtual import presets

N = 200_000


def c_ns_per_step(controller, vs, precision, workdir: Path, limits) -> tuple[float, float]:
    """ns per step of the generated C, safety layer included (a run that held would be
    faster than a real one: the benchmark refuses it)."""
    prefix = f"b_{precision[0]}"
    render_c(controller, precision, prefix, vs=vs, limits=limits).write(workdir)
    lib = workdir / f"lib{prefix}.so"
    subprocess.run(
        ["gcc", "-std=c99", "-O2", "-fPIC", "-shared", "-o", str(lib), str(workdir / f"{prefix}.c"), "-lm"],
        check=True,
    )
    so = ctypes.CDLL(str(lib))
    dt = np.float32 if precision == "single" else np.float64
    ct = ctypes.c_float if precision == "single" else ctypes.c_double
    a = (100.0 * np.sin(np.arange(N) * 0.01)).astype(dt)
    w = (-50.0 * np.cos(np.arange(N) * 0.003)).astype(dt)
    u, z = np.zeros(N, dt), np.zeros(N, dt)
    p = lambda x: x.ctypes.data_as(ctypes.POINTER(ct))  # noqa: E731
    state = ctypes.create_string_buffer(getattr(so, f"{prefix}_state_size")())
    best_ctl = best_mil = float("inf")
    for _ in range(5):
        getattr(so, f"{prefix}_init")(state)
        t0 = time.perf_counter()
        getattr(so, f"{prefix}_run")(state, p(a), p(w), p(u), ctypes.c_long(N))
        best_ctl = min(best_ctl, time.perf_counter() - t0)
        getattr(so, f"{prefix}_init")(state)
        t0 = time.perf_counter()
        getattr(so, f"{prefix}_mil_run")(state, p(a), p(w), p(u), p(z), ctypes.c_long(N))
        best_mil = min(best_mil, time.perf_counter() - t0)
        if getattr(so, f"{prefix}_fault")(state) & HOLD:
            raise SystemExit("the benchmark's record made the safety layer hold: choose another")
    return best_ctl / N * 1e9, best_mil / N * 1e9


def python_us_per_step(controller, vs, precision) -> float:
    rt = MILRuntime(controller, vs=vs, precision=precision)
    rt.mil_step(0.0, 0.0)  # compile
    n = 20_000
    t0 = time.perf_counter()
    for _ in range(n):
        rt.mil_step(1.0, 2.0)
    return (time.perf_counter() - t0) / n * 1e6


def main() -> None:
    design = design_controller(
        table_model(TableParameters.report_default()), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    controller = controller_from_design(design)
    vs = presets.get("SD2")
    loop_ns = controller.loop_time_s * 1e9
    with tempfile.TemporaryDirectory() as d:
        for precision in ("single", "double"):
            ctl_ns, mil_ns = c_ns_per_step(controller, vs, precision, Path(d), command_limits(design.table))
            py_us = python_us_per_step(controller, vs, precision)
            print(
                f"{precision:6s}  C step {ctl_ns:6.1f} ns ({ctl_ns / loop_ns:.3%} of the "
                f"{loop_ns / 1e3:.0f} us loop)   C MIL step (SD2 + RK3) {mil_ns:6.1f} ns "
                f"({mil_ns / loop_ns:.3%})   Python MILRuntime.mil_step {py_us:6.2f} us "
                f"({py_us * 1e3 / mil_ns:.0f}x the C MIL step)"
            )


if __name__ == "__main__":
    main()
