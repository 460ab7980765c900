"""Shared models for the design tests: the report's table and the SD2 isolator.

The table transfer functions are built here from the closed forms of
Eq 4-15a and 4-15d with Table 4.1 parameters (d = 1e5, docs/errata.md), an
independent route from :mod:`impedance_mil.plant`'s state space; one test
(test_adapters.py) checks that the two agree.  The SD transfer functions
come from Eq 5-2 with Table 9.1 (SD2, m_vs = 2000 lb ~ 1.25 m_st).
"""

import numpy as np
import pytest

from impedance_mil.design import TableModel, VirtualModel
from impedance_mil.systems import TransferFunction
from impedance_mil.units import G0, TWO_PI

# Table 4.1 (d corrected to 1e5, see docs/errata.md)
KE, KP, KV, TAU = 5.0, 0.001, 3.0, 500e-6
AP, XM, MST, D = 2.1, 3.2, 4.14, 1e5
A1, A2, ZETA_OIL, W_OIL = TWO_PI * 70, TWO_PI * 110, 0.09, TWO_PI * 27


def closed_form_table(Ke=KE, Kp=KP, tau=TAU, m=MST, d=D) -> TableModel:
    """H_zu and H_zw of Eq 4-15a and 4-15d."""
    g, de, eps = A1 * A2, A1 + A2, 2 * ZETA_OIL * W_OIL
    K = g * d * AP * KV * Ke / m
    den = [
        1.0,
        de + eps,
        W_OIL**2 + de * eps + g - g * d * KV * Kp * tau,
        de * W_OIL**2 + g * eps + g * d * KV * Kp,
        g * W_OIL**2 - K * tau,
        K,
    ]
    H_zu = TransferFunction([K, 0.0, 0.0], den)
    H_zw = TransferFunction(
        np.array([1.0, de + eps, de * eps + g - g * d * KV * Kp * tau, g * eps + g * d * KV * Kp, 0.0, 0.0])
        / m,
        den,
    )
    return TableModel(H_zu, H_zw, tau, {"Ke": Ke, "Kp": Kp, "loop_time": tau, "mass": m, "d": d})


def sd_model(m_vs=2000.0 / G0, k=894.0, c=57.0, name="SD2") -> VirtualModel:
    """Eq 5-2 with Table 9.1 values (k_s [lbf/in], c [lbf*s/in], m_vs [lbf*s^2/in])."""
    den = [m_vs, c, k]
    return VirtualModel(
        TransferFunction([c, k], den),
        TransferFunction([1.0, 0.0, 0.0], den),
        None,
        kind="SD",
        name=name,
        parameters={"m_vs": m_vs, "k_s": k, "c": c},
    )


def lr_model(m_vs=2000.0 / G0, k_i=2353.0, c=0.15, q_d=839.0) -> VirtualModel:
    """Linear part of LR2 (Eq 5-8a, 5-8b; H_zfh with the strength q_d, see test_forms)."""
    den = [m_vs, c, k_i]
    return VirtualModel(
        TransferFunction([c, k_i], den),
        TransferFunction([1.0, 0.0, 0.0], den),
        TransferFunction([q_d, 0.0], den),
        kind="LR",
        name="LR2",
    )


def fp_model(m_vs=2150.0 / G0, k_s=187.0) -> VirtualModel:
    """Linear part of FP2 (Eq 5-13)."""
    den = [m_vs, 0.0, k_s]
    return VirtualModel(
        TransferFunction([k_s], den),
        TransferFunction([1.0, 0.0, 0.0], den),
        TransferFunction([-1.0, 0.0, 0.0], den),
        kind="FP",
        name="FP2",
    )


@pytest.fixture(scope="session")
def table():
    return closed_form_table()


@pytest.fixture(scope="session")
def sd2():
    return sd_model()
