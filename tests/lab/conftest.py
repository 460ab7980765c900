"""Shared fixtures of the lab tests: the report's Table 4.1 parameters."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.plant import TableParameters


def report_parameters() -> TableParameters:
    """Table 4.1 with d = 1e5 (the text of Section 4.3.5; Table 4.1's 3e5 is a misprint)."""
    return TableParameters.report_default()


@pytest.fixture
def table41():
    return report_parameters()


def eq_4_14b(p):
    """Eq 4-14b state space (A, B_u, B_w), written out from the report, analog controller."""
    w = 2 * np.pi * p.f_oil_hz
    a1, a2 = (2 * np.pi * f for f in p.valve_poles_hz)
    gam, dlt, eps = a1 * a2, a1 + a2, 2 * p.zeta_oil * w
    m, area = p.mass, p.piston_area
    A = np.array(
        [
            [0, 1, 0, 0, 0],
            [0, 0, area / m, 0, 0],
            [0, -(w**2) * m / area, -eps, p.d, 0],
            [0, 0, 0, 0, 1],
            [-p.Kv * p.Ke * gam, 0, -p.Kv * p.Kp * gam, -gam, -dlt],
        ],
        dtype=float,
    )
    B_u = np.array([0, 0, 0, 0, p.Kv * p.Ke * gam], dtype=float)
    B_w = np.array([0, 1 / m, 0, 0, 0], dtype=float)
    return A, B_u, B_w


def eq_4_11(p):
    """Eq 4-11 state space (A, B_i, B_w): input valve current u_i [mA]."""
    A, _, B_w = eq_4_14b(p)
    A = A.copy()
    a1, a2 = (2 * np.pi * f for f in p.valve_poles_hz)
    A[4, 0] = A[4, 2] = 0.0
    B_i = np.array([0, 0, 0, 0, a1 * a2], dtype=float)
    return A, B_i, B_w


def ss_response(A, b, c, d, f_hz):
    """Complex frequency response of (A, b, c, d) at f_hz [Hz]."""
    n = A.shape[0]
    return np.array([c @ np.linalg.solve(2j * np.pi * f * np.eye(n) - A, b) + d for f in f_hz])
