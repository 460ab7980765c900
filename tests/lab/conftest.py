"""Shared fixtures of the lab tests: the report's Table 4.1 parameters."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

try:  # the plant package provides the canonical parameter object
    from impedance_mil.plant import TableParameters as _TableParameters
except ImportError:  # pragma: no cover - only until impedance_mil.plant lands
    _TableParameters = None


@dataclass(frozen=True)
class _Table41:
    """Report Table 4.1 with d = 1e5 (the text of Section 4.3.5; 3e5 in the table is a misprint)."""

    Ke: float = 5.0
    Kp: float = 0.001
    Kv: float = 3.0
    loop_time: float = 500e-6
    piston_area: float = 2.1
    mid_stroke: float = 3.2
    mass: float = 4.14
    d: float = 1.0e5
    valve_poles_hz: tuple = (70.0, 110.0)
    zeta_oil: float = 0.09
    f_oil_hz: float = 27.0
    supply_pressure: float = 3000.0
    return_pressure: float = 0.0
    rated_flow: float = 57.75
    rated_pressure_drop: float = 1000.0
    rated_current: float = 25.0
    valve_command_limit: float = 10.0


def report_parameters():
    """Table 4.1 parameters, from ``impedance_mil.plant`` when available."""
    if _TableParameters is not None:
        return _TableParameters.report_default()
    return _Table41()


@pytest.fixture
def table41():
    return report_parameters()


def eq_4_14b(p):
    """Eq 4-14b state space (A, B_u, B_w), written out from the report, analog controller."""
    w = 2 * np.pi * p.f_oil_hz
    a1, a2 = (2 * np.pi * f for f in p.valve_poles_hz)
    gam, dlt, eps = a1 * a2, a1 + a2, 2 * p.zeta_oil * w
    m, area = p.mass, p.piston_area
    A = np.array([
        [0, 1, 0, 0, 0],
        [0, 0, area / m, 0, 0],
        [0, -w ** 2 * m / area, -eps, p.d, 0],
        [0, 0, 0, 0, 1],
        [-p.Kv * p.Ke * gam, 0, -p.Kv * p.Kp * gam, -gam, -dlt],
    ], dtype=float)
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
