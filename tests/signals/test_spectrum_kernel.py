"""The vectorized peak kernel of the response spectrum against the loop it replaced (issue 16).

``signals.spectrum._peak_responses`` runs all oscillators at once, samples in the
outer loop.  The reference below is the kernel it replaced, one oscillator at a
time, written here in plain Python: the same expression in the same order for
every oscillator, so the peaks must agree bit for bit (no tolerance), which
also keeps every metric and JSON figure of a run unchanged.
"""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.signals import builtin_motion, response_spectrum
from impedance_mil.signals.spectrum import _coefficients, _peak_responses


def _peaks_one_oscillator_at_a_time(accel, a_coef, b_coef):
    """The kernel before issue 16 (periods outer, samples inner), as plain Python."""
    peaks = np.zeros(a_coef.shape[0])
    for j in range(a_coef.shape[0]):
        a11, a12, a21, a22 = a_coef[j, 0, 0], a_coef[j, 0, 1], a_coef[j, 1, 0], a_coef[j, 1, 1]
        b11, b12, b21, b22 = b_coef[j, 0, 0], b_coef[j, 0, 1], b_coef[j, 1, 0], b_coef[j, 1, 1]
        u = v = peak = 0.0
        for k in range(accel.size - 1):
            a0, a1 = accel[k], accel[k + 1]
            u_next = a11 * u + a12 * v + b11 * a0 + b12 * a1
            v = a21 * u + a22 * v + b21 * a0 + b22 * a1
            u = u_next
            peak = max(peak, abs(u))
        peaks[j] = peak
    return peaks


@pytest.mark.parametrize(
    ("n_periods", "damping"),
    [(1, 0.05), (7, 0.0), (40, 0.05), (13, 1.5)],  # one lane, a ragged count, a band's 40, overdamped
)
def test_vectorized_peaks_equal_the_one_at_a_time_loop(n_periods, damping):
    gm = builtin_motion("elcentro")
    accel = np.ascontiguousarray(gm.accel[:1500])  # the strong part: 15 s at 0.01 s
    omegas = 2 * np.pi / np.geomspace(0.02, 5.0, n_periods)
    a_coef, b_coef = _coefficients(omegas, damping, gm.time_step)
    got = _peak_responses(accel, a_coef, b_coef)
    ref = _peaks_one_oscillator_at_a_time(accel, a_coef, b_coef)
    assert np.all(ref > 0)
    np.testing.assert_array_equal(got, ref)


def test_response_spectrum_is_the_same_whatever_the_periods_next_to_it():
    """Each oscillator's peak depends on its own period only (no lane mixes with another)."""
    gm = builtin_motion("elcentro")
    periods = np.geomspace(0.05, 4.0, 9)
    together = response_spectrum(gm.accel, gm.time_step, periods).psa
    alone = np.array([response_spectrum(gm.accel, gm.time_step, [p]).psa[0] for p in periods])
    np.testing.assert_array_equal(together, alone)
