"""Balanced singular perturbation of a controller path (issue 15, "Realization").

References: the Hankel singular value of ``k/(s + a)`` is ``|k|/(2a)``
(closed form: Gramians ``1/(2a)`` and ``k**2/(2a)``); the H-infinity error
bound ``2 * sum`` of the removed values (Liu and Anderson 1989, as for
balanced truncation); singular perturbation keeps the DC gain.
"""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.design.optimized.basis import PoleBasis
from impedance_mil.design.optimized.certify import StateSpace, path_state_space
from impedance_mil.design.optimized.realize import realize
from impedance_mil.design.optimized.reduce import (
    hankel_singular_values,
    reduce_path,
    reduce_stable,
    transfer_function,
)
from impedance_mil.errors import ConfigError
from impedance_mil.units import TWO_PI


def test_hankel_value_of_a_first_order_lag_is_the_closed_form():
    # k/(s + a) with a = 3, k = 4: sigma = |k|/(2a) = 2/3.
    sig = hankel_singular_values(np.array([[-3.0]]), np.array([2.0]), np.array([2.0]))
    assert sig[0] == pytest.approx(4.0 / 6.0, rel=1e-12)


def _random_path(seed: int):
    """A C_w-like path on the default basis with random coefficients (18 stable states)."""
    basis = PoleBasis.butterworth_groups(max_hz=1000.0)
    rng = np.random.default_rng(seed)
    return basis, rng.normal(size=basis.n_w), rng.normal(size=basis.n_z)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_error_stays_below_the_bound_and_dc_is_exact(seed):
    basis, xw, _ = _random_path(seed)
    path = path_state_space(basis, xw, "w")
    f = np.logspace(-2, 4, 3000)
    s = 1j * TWO_PI * f
    full = path.response(s)
    for order in (4, 8, 12, 16):
        r = reduce_path(path, 0, order)
        err = np.max(np.abs(r.state_space.response(s) - full))
        assert r.order_after == order and r.order_before == 18
        assert err <= r.bound * (1 + 1e-6)  # the a-priori bound holds (measured 0.3-1.0 of it)
        assert err >= 0.9 * r.hankel[order]  # any order-r model is >= sigma_{r+1} off (grid: 0.9 of it)
        dc = r.state_space.response(np.array([1e-9j]))[0] / path.response(np.array([1e-9j]))[0]
        assert abs(dc - 1) < 1e-9  # singular perturbation keeps the DC gain


def test_integrators_are_kept_and_full_order_is_exact():
    basis, _, xz = _random_path(4)
    path = path_state_space(basis, xz, "z")
    r = reduce_path(path, 2, 8)
    assert np.allclose(np.linalg.eigvals(r.state_space.A[:2, :2]), 0.0)
    s = 1j * TWO_PI * np.logspace(-3, -2, 5)  # near DC the double integrator dominates: same a_2, a_1
    assert np.allclose(r.state_space.response(s), path.response(s), rtol=1e-6)
    same = reduce_path(path, 2, 20).state_space
    f = 1j * TWO_PI * np.logspace(-1, 3, 200)
    assert np.max(np.abs(same.response(f) / path.response(f) - 1)) < 1e-9


def test_transfer_function_from_eigenvalues_matches_the_realization():
    basis, xw, _ = _random_path(5)
    r = reduce_path(path_state_space(basis, xw, "w"), 0, 10).state_space
    H = transfer_function(r)
    s = 1j * TWO_PI * np.logspace(-1, 3, 200)
    assert H.order == 10
    assert np.max(np.abs(H(s) / r.response(s) - 1)) < 1e-9


def test_truncation_is_exact_at_high_frequency_and_bad_input_refused():
    A = np.diag([-1.0, -50.0])
    r = reduce_stable(A, np.ones(2), np.ones(2), 0.5, 1, method="truncate")
    assert r.D == 0.5 and r.order == 1
    with pytest.raises(ConfigError, match="reduce"):
        reduce_stable(A, np.ones(2), np.ones(2), 0.0, -1)
    with pytest.raises(ConfigError, match="residualize or truncate"):
        reduce_stable(A, np.ones(2), np.ones(2), 0.0, 1, method="modal")
    with pytest.raises(ConfigError, match="at least 2"):
        reduce_path(StateSpace(np.zeros((2, 2)), np.ones(2), np.ones(2), 0.0), 2, 1)


def test_an_order_with_a_pole_above_nyquist_is_refused_and_auto_avoids_it():
    # Residualization that cuts through a complex pair leaves one fast real pole; the implementation
    # step needs every pole below the Nyquist frequency, so such an order is refused in one line.
    basis, xw, xz = _random_path(6)
    always = lambda *a: {"I": True, "II": True, "III": True, "certified": True}  # noqa: E731
    path = path_state_space(basis, xw, "w")
    refused = 0
    for order in range(2, 18):
        fast = np.max(np.abs(np.linalg.eigvals(reduce_path(path, 0, order).state_space.A))) / TWO_PI
        zfast = np.max(
            np.abs(np.linalg.eigvals(reduce_path(path_state_space(basis, xz, "z"), 2, order).state_space.A))
        )
        if max(fast, zfast / TWO_PI) >= 1000.0:
            refused += 1
            with pytest.raises(ConfigError, match="Nyquist"):
                realize(basis, xz, xw, order, 1e-3, (0.25, 15.0), 1000.0, always)
    assert refused > 0  # the case exists on this path
    real = realize(basis, xz, xw, "auto", 1e-3, (0.25, 15.0), 1000.0, always)
    for ss in (real.C_z, real.C_w):
        assert np.max(np.abs(np.linalg.eigvals(ss.A))) / TWO_PI < 1000.0
    assert real.record["orders_after"]["H_uw"] < 18
