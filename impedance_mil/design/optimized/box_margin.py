"""Worst passivity margin of ``H = a + beta/(N - p)`` over a rectangle of complex ``N``, in closed form.

At one frequency the controlled table's force-velocity response is affine in
the VS impedance, ``H_vw = a + b Z``, and the describing-function impedance of
a hysteretic VS is a Moebius function of its complex stiffness ``N``:
``Z = -w**2/(N - m w**2)``.  So ``H_vw = a + beta/(N - p)`` with
``beta = -w**2 b`` and the real pole ``p = m w**2``.

When ``N`` ranges over a closed rectangle ``[x0, x1] x [y0, y1]`` that does
not contain ``p``, ``H`` is analytic on it, and:

* if ``H`` has no zero in the rectangle, a continuous branch of ``arg H`` is
  harmonic there, so its maximum and minimum lie on the boundary (maximum
  principle); ``max |arg H|`` is then the largest ``|arg H|`` on the four edges;
* if ``H`` has a zero inside, the image of the boundary winds once around the
  origin (argument principle) and so crosses the negative real axis, where
  ``|arg H| = 180 deg`` is found on an edge too.

On an edge ``N = N0 + t d``, ``t`` in [0, 1], ``H(t) = (P + Q t)/(D0 + d t)``
with ``D0 = N0 - p``, ``P = a D0 + beta``, ``Q = a d``: a circle arc.  The
largest ``|arg H|`` on it is at an end, where ``d arg H/dt = 0`` (a quadratic
in ``t``: ``Im(Q P*) |D0 + d t|**2 = Im(d D0*) |P + Q t|**2``), or where the
arc crosses the negative real axis (``Im((P + Q t)(D0 + d t)*) = 0``, a
quadratic too).  Evaluating those at most six points per edge gives the exact
worst margin ``90 - max |arg H|`` [deg] over the rectangle, with no sampling.
"""

from __future__ import annotations

import numpy as np


def _roots_in_unit_interval(c2, c1, c0) -> list[np.ndarray]:
    """Real roots of ``c2 t**2 + c1 t + c0`` in [0, 1] (others, and no root, become 0: an end point)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        disc = c1 * c1 - 4.0 * c2 * c0
        sq = np.sqrt(np.where(disc >= 0.0, disc, np.nan))
        q = -0.5 * (c1 + np.copysign(sq, c1))  # stable form: no cancellation, c2 -> 0 gives the linear root
        roots = [q / c2, c0 / q]
    return [np.where(np.isfinite(t) & (t >= 0.0) & (t <= 1.0), t, 0.0) for t in roots]


def _edge_worst_deg(a, beta, p, N0, d) -> np.ndarray:
    """Smallest ``90 - |arg H|`` [deg] on the edge ``N0 + t d``, ``t`` in [0, 1] (see the module docstring)."""
    D0 = N0 - p
    P = a * D0 + beta
    Q = a * d
    k1 = np.imag(Q * np.conj(P))
    k2 = np.imag(d * np.conj(D0))
    q0, q1, q2 = np.abs(D0) ** 2, 2.0 * np.real(D0 * np.conj(d)), np.abs(d) ** 2
    r0, r1, r2 = np.abs(P) ** 2, 2.0 * np.real(P * np.conj(Q)), np.abs(Q) ** 2
    candidates = [np.zeros_like(q0), np.ones_like(q0)]
    candidates += _roots_in_unit_interval(k1 * q2 - k2 * r2, k1 * q1 - k2 * r1, k1 * q0 - k2 * r0)
    candidates += _roots_in_unit_interval(
        np.imag(Q * np.conj(d)), np.imag(P * np.conj(d) + Q * np.conj(D0)), np.imag(P * np.conj(D0))
    )
    worst = np.full(np.shape(q0), np.inf)
    for t in candidates:
        with np.errstate(divide="ignore", invalid="ignore"):  # N on the pole: H infinite, margin -90 below
            H = (P + Q * t) / (D0 + d * t)
        worst = np.minimum(worst, np.where(np.isfinite(H), 90.0 - np.abs(np.degrees(np.angle(H))), -90.0))
    return worst


def worst_margin_deg(a, beta, p, x0, x1, y0, y1) -> np.ndarray:
    """Exact ``min (90 - |arg H|)`` [deg] of ``H = a + beta/(N - p)`` over ``x0 <= Re N <= x1``, ``y0 <= Im N <= y1``.

    Parameters
    ----------
    a, beta : array_like of complex
        ``H`` with the VS impedance zero [in/s per lbf], and ``-w**2 b`` with
        ``b = dH/dZ`` [in/s per lbf times lbf/in]: any units in which
        ``a + beta/(N - p)`` is consistent, since only the phase of ``H`` matters.
    p : array_like of float
        Real pole ``m w**2`` [lbf/in].
    x0, x1, y0, y1 : array_like of float
        Bounds of ``Re N`` and ``Im N`` [lbf/in], ``x0 <= x1``, ``y0 <= y1``; a
        degenerate rectangle (a point) gives the margin at that point.

    Returns
    -------
    ndarray
        The worst margin [deg], in [-90, 90]; -90 where the rectangle contains ``p``
        (``H`` unbounded there).  Broadcast over the arguments.

    Examples
    --------
    >>> float(worst_margin_deg(0.0, 1.0, 0.0, 1.0, 1.0, -1.0, 1.0))  # 1/N on Re N = 1, |Im N| <= 1
    45.0
    """
    a, beta, p, x0, x1, y0, y1 = np.broadcast_arrays(*(np.asarray(v) for v in (a, beta, p, x0, x1, y0, y1)))
    a = a.astype(complex)
    beta = beta.astype(complex)
    width = (x1 - x0).astype(float)
    height = 1j * (y1 - y0)
    worst = np.minimum.reduce(
        [
            _edge_worst_deg(a, beta, p, x0 + 1j * y0, width),
            _edge_worst_deg(a, beta, p, x0 + 1j * y1, width),
            _edge_worst_deg(a, beta, p, x0 + 1j * y0, height),
            _edge_worst_deg(a, beta, p, x1 + 1j * y0, height),
        ]
    )
    pole_inside = (x0 <= p) & (p <= x1) & (y0 <= 0.0) & (y1 >= 0.0)
    return np.where(pole_inside, -90.0, worst)
