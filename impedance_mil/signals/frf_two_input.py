"""Two-input FRF from several periodic tests: the command path ``y/u`` and the force path ``y/w`` apart.

A table's response to its command ``u`` and to the article's force ``w`` is
``Y = H_yu U + H_yw W`` at each line.  One test cannot separate the two paths
once an article is on the table (``w`` then follows the table's own motion, so
``W`` is a fixed multiple of ``U`` at each line), and a bare table has no ``w``
at all.  Two or more tests whose ``W/U`` differ, for example the bare table and
the table with a rigid mass, or two article masses, give at each line the
linear system::

    [Y_1 ... Y_R] = [H_yu  H_yw] [[U_1 ... U_R],
                                  [W_1 ... W_R]]

solved by least squares (exactly for R = 2) on the synchronous averages of each
test's periods (Pintelon and Schoukens 2012, *System Identification: A
Frequency Domain Approach*, 2nd ed., Section 2.7, multiple-input FRFs from
multiple experiments).  Averaging the periods first removes the noise of the
measured ``w`` from the regressors before the solve (errors in variables).

The standard deviation of each path follows from the per-period residuals
``E = Y_p - H [U_p, W_p]`` of each test (``P - 1`` degrees of freedom, smoothed
over neighbouring lines as in :mod:`impedance_mil.signals.frf_estimators`),
propagated through the solve: ``Cov(H) = (X X^H)^-1 X S X^H (X X^H)^-1`` with
``S = diag(sigma_r^2 / P_r)``.  The residual holds the noise of ``y`` and
that of ``w`` through ``H_yw``.  ``coherence`` is the multiple coherence
``1 - sum |E|^2 / sum |Y_p|^2`` over every test and period, and
``condition`` the condition number of the row-normalized ``X`` at each line: a
second test that differs too little from the first (``W/U`` nearly the same)
gives an ill-conditioned solve, refused above :data:`MAX_CONDITION`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from .frf import FRF
from .frf_estimators import SMOOTHING_LINES, STD_FLOOR, period_spectra, smoothed

#: Largest condition number of the normalized inputs at a line: beyond it the two
#: tests do not separate the paths (their ``W/U`` are too alike).
MAX_CONDITION = 1e3


@dataclass(frozen=True, eq=False)
class TwoInputFRF:
    """The command and force paths of a response, estimated from several tests.

    Attributes
    ----------
    command : FRF
        ``y/u`` at the lines [output unit per in], with its standard deviation
        and the multiple coherence.
    force : FRF
        ``y/w`` at the lines [output unit per lbf], same coherence.
    condition : ndarray
        Condition number of the row-normalized input matrix at each line (1 is best).
    n_tests : int
        Number of tests solved together.
    """

    command: FRF
    force: FRF
    condition: np.ndarray
    n_tests: int


def two_input_frf(
    tests: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]],
    n_points: int,
    sample_rate_hz: float,
    lines,
    discard_periods: int = 1,
) -> TwoInputFRF:
    """Separate ``y/u`` and ``y/w`` from two or more periodic tests of the same drive.

    Parameters
    ----------
    tests : sequence of (u, w, y)
        Each test's command [in], article force [lbf] and response [output unit],
        whole periods of the multisine.
    n_points : int
        Samples per period.
    sample_rate_hz : float
        Sampling rate [Hz].
    lines : array_like of int
        Excited FFT bins of one period.
    discard_periods : int
        Leading periods dropped as transient.

    Raises
    ------
    ConfigError
        Fewer than two tests, fewer than two periods after the transient in a
        test, or tests that do not separate the paths (condition number above
        :data:`MAX_CONDITION` at some line: naming the frequency).
    """
    if len(tests) < 2:
        raise ConfigError(
            "recordings", "two or more tests whose article force differs (e.g. bare table and a mass)"
        )
    lines = np.asarray(lines, dtype=int)
    spectra = [tuple(period_spectra(sig, n_points, lines, discard_periods) for sig in test) for test in tests]
    if min(s[0].shape[0] for s in spectra) < 2:
        raise ConfigError("frf.n_periods", "at least two periods after the transient in every test")
    # X: (lines, 2, R) inputs, Y: (lines, R) responses, from each test's period average.
    X = np.stack([np.stack([u.mean(0), w.mean(0)], axis=0) for u, w, _ in spectra], axis=-1).transpose(
        1, 0, 2
    )
    Y = np.stack([y.mean(0) for _, _, y in spectra], axis=-1)
    gram = X @ np.conj(X).transpose(0, 2, 1)  # (lines, 2, 2)
    rhs = np.einsum("kr,kir->ki", Y, np.conj(X))  # Y X^H
    normalized = X / np.linalg.norm(X, axis=2, keepdims=True)
    condition = np.linalg.cond(normalized)
    worst = int(np.argmax(condition))
    f = lines * sample_rate_hz / n_points
    if not condition[worst] <= MAX_CONDITION:
        raise ConfigError(
            "recordings",
            f"tests whose article force differs enough to separate y/u from y/w (condition number "
            f"{condition[worst]:.3g} at {f[worst]:.4g} Hz; at most {MAX_CONDITION:g}: use another article mass)",
        )
    H = np.linalg.solve(np.conj(gram), rhs[..., None])[..., 0]  # H (X X^H) = Y X^H
    # Noise of each test from its per-period residuals, then propagated through the solve.
    total_e = np.zeros(lines.size)
    total_y = np.zeros(lines.size)
    s_diag = []
    for u, w, y in spectra:
        e = y - H[:, 0] * u - H[:, 1] * w
        p = u.shape[0]
        var = smoothed(np.sum(np.abs(e) ** 2, axis=0) / (p - 1), SMOOTHING_LINES)
        s_diag.append(var / p)
        total_e += np.sum(np.abs(e) ** 2, axis=0)
        total_y += np.sum(np.abs(y) ** 2, axis=0)
    S = np.stack(s_diag, axis=-1)  # (lines, R)
    inv = np.linalg.inv(gram)
    middle = np.einsum("kir,kr,kjr->kij", X, S, np.conj(X))
    cov = inv @ middle @ np.conj(inv).transpose(0, 2, 1)
    std = np.sqrt(np.maximum(np.real(np.stack([cov[:, 0, 0], cov[:, 1, 1]], axis=-1)), 0.0))
    std = np.maximum(std, STD_FLOOR * np.abs(H))
    coherence = np.clip(1.0 - total_e / np.maximum(total_y, np.finfo(float).tiny), 1e-12, 1.0)
    periods = min(s[0].shape[0] for s in spectra)
    return TwoInputFRF(
        FRF(f, H[:, 0], coherence, periods, std[:, 0]),
        FRF(f, H[:, 1], coherence, periods, std[:, 1]),
        condition,
        len(tests),
    )


__all__ = ["MAX_CONDITION", "TwoInputFRF", "two_input_frf"]
