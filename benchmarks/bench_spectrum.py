"""Benchmark: 5 %-damped spectrum, 100 periods, 60 s record at 2000 Hz (120 001 samples).

Goal (issue 3): well under a second on one core.  Prints our time, the time of
a straightforward reference (scipy.signal.lsim with linear input
interpolation, one call per period) measured on a subset of periods in the
same run and extrapolated per period, the speed-up ratio, and the largest
relative difference of the spectral displacements on that subset.

Run: ``.venv/bin/python benchmarks/bench_spectrum.py``
"""

from __future__ import annotations

import time

import numpy as np
from scipy.signal import lsim

from impedance_mil.signals import DEFAULT_PERIODS, builtin_motion, response_spectrum

LOOP_RATE_HZ = 2000.0
DURATION_S = 60.0
REFERENCE_PERIODS = 4


def _record() -> tuple[np.ndarray, float]:
    """El Centro (RSN 6), time-compressed by 2 and scaled to 0.8 g (report GM1), at 2000 Hz, 60 s."""
    gm = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8).resampled(1.0 / LOOP_RATE_HZ)
    n = int(DURATION_S * LOOP_RATE_HZ) + 1
    accel = np.zeros(n)
    accel[: min(n, gm.npts)] = gm.accel[:n]
    return accel, gm.time_step


def main() -> None:
    accel, dt = _record()
    response_spectrum(accel[:100], dt, DEFAULT_PERIODS)  # compile (or load the cached kernel)
    runs = []
    for _ in range(3):
        start = time.perf_counter()
        spec = response_spectrum(accel, dt, DEFAULT_PERIODS, damping=0.05)
        runs.append(time.perf_counter() - start)
    ours = min(runs)

    subset = DEFAULT_PERIODS[:: len(DEFAULT_PERIODS) // REFERENCE_PERIODS][:REFERENCE_PERIODS]
    t = np.arange(accel.size) * dt
    start = time.perf_counter()
    ref_sd = []
    for period in subset:
        w = 2 * np.pi / period
        _, y, _ = lsim(([-1.0], [1.0, 0.1 * w, w * w]), accel, t)
        ref_sd.append(np.max(np.abs(y)))
    per_period = (time.perf_counter() - start) / subset.size
    reference = per_period * DEFAULT_PERIODS.size
    ours_subset = response_spectrum(accel, dt, subset, damping=0.05).sd
    rel = np.max(np.abs(ours_subset - np.array(ref_sd)) / np.array(ref_sd))

    print(
        f"record: {accel.size} samples at {1 / dt:.0f} Hz; {DEFAULT_PERIODS.size} periods "
        f"{DEFAULT_PERIODS[0]:.3g}-{DEFAULT_PERIODS[-1]:.3g} s; PSA(0.01 s) = {spec.psa_g[0]:.4f} g"
    )
    print(f"response_spectrum (Nigam-Jennings, compiled): {ours * 1e3:.1f} ms (best of 3)")
    print(
        f"reference scipy.signal.lsim per period: {per_period * 1e3:.1f} ms/period measured on "
        f"{subset.size} periods -> {reference:.2f} s for {DEFAULT_PERIODS.size}"
    )
    print(f"speed-up ratio: {reference / ours:.0f}x; max relative SD difference on the subset: {rel:.2e}")
    print(f"goal (< 1 s): {'met' if ours < 1.0 else 'NOT met'}")


if __name__ == "__main__":
    main()
