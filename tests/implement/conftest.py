"""Fixtures for the implementation tests: a representative standardized controller.

The controller is built here, independently of :mod:`impedance_mil.design`,
from the closed forms of the report's Eq. 4-15a/4-15d with the Table 4.1
parameters (d = 1e5 lbf*mA/in**5/V; the 3e5 printed in Table 4.1 contradicts
the text of Section 4.3.5, see docs/errata.md) and a 3rd-order Butterworth
low-pass filter at f_c = 80 Hz (Eq. 6-10):

    H_uz = F / H_zu,      H_uw = -F * H_zw / H_zu       (Eq. 6-7, Section 6.5)
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.signal

from impedance_mil.implement import discretize
from impedance_mil.implement.safety import CommandLimits
from impedance_mil.systems import TransferFunction

TWO_PI = 2.0 * math.pi

#: Table 4.1 (with d = 1e5), report units.
TABLE_4_1 = dict(
    Ke=5.0,
    Kp=0.001,
    Kv=3.0,
    tau=500e-6,
    Ap=2.1,
    xm=3.2,
    m=4.14,
    d=1e5,
    a1=TWO_PI * 70.0,
    a2=TWO_PI * 110.0,
    zeta=0.09,
    w_oil=TWO_PI * 27.0,
)

LOOP_TIME_S = 500e-6
FC_HZ = 80.0

# -O2 with the arithmetic kept as written (the generated header asks for these flags when
# results must reproduce the runtime bit for bit): gcc 12's basic-block vectorization and its
# folding of powf(x, 2) change float results of the TFP step by a rounding (docs/implement.md).
GCC_FLAGS = [
    "-std=c99",
    "-O2",
    "-fno-tree-slp-vectorize",
    "-fno-builtin",
    "-Wall",
    "-Wextra",
    "-Werror",
    "-pedantic",
    "-fPIC",
    "-shared",
]

#: Safety-layer limits beyond every value of the test records (the synthetic record drifts
#: to a peak u of 61 in): no guard acts, and the bit-identity tests assert that the fault
#: word stays 0.  The guards themselves are tested in test_codegen_guards.py.
WIDE_LIMITS = CommandLimits(stroke_in=1e4, max_rate_in_s=1e6, accel_limit_in_s2=1e6, force_limit_lbf=1e7)


def table_tfs(p=TABLE_4_1):
    """H_zu (Eq. 4-15a) and H_zw (Eq. 4-15d) [rad/s polynomials]."""
    delta = p["a1"] + p["a2"]
    gamma = p["a1"] * p["a2"]
    eps = 2.0 * p["zeta"] * p["w_oil"]
    w2 = p["w_oil"] ** 2
    k0 = gamma * p["d"] * p["Ap"] * p["Kv"] * p["Ke"] / p["m"]
    den = [
        1.0,
        delta + eps,
        w2 + delta * eps + gamma - gamma * p["d"] * p["Kv"] * p["Kp"] * p["tau"],
        delta * w2 + gamma * eps + gamma * p["d"] * p["Kv"] * p["Kp"],
        gamma * w2 - k0 * p["tau"],
        k0,
    ]
    h_zu = TransferFunction([k0, 0.0, 0.0], den)
    num_zw = (
        np.array(
            [
                1.0,
                delta + eps,
                delta * eps + gamma - gamma * p["d"] * p["Kv"] * p["Kp"] * p["tau"],
                gamma * eps + gamma * p["d"] * p["Kv"] * p["Kp"],
                0.0,
                0.0,
            ]
        )
        / p["m"]
    )
    h_zw = TransferFunction(num_zw, den)
    return h_zu, h_zw


def butterworth(fc_hz=FC_HZ, order=3):
    """Analog Butterworth low-pass (MATLAB ``butter(n, 2*pi*fc, 'low', 's')``)."""
    b, a = scipy.signal.butter(order, TWO_PI * fc_hz, "low", analog=True)
    return TransferFunction(b, a)


def standardized_controller(fc_hz=FC_HZ, p=TABLE_4_1):
    """(H_uz, H_uw) of the standardized controller, filtered (Section 6.5 Steps 1-3)."""
    h_zu, h_zw = table_tfs(p)
    f = butterworth(fc_hz)
    h_uz = (f / h_zu).minreal()
    h_uw = (-(f * h_zw / h_zu)).minreal()
    return h_uz, h_uw


def broadband_record(duration_s=60.0, dt=LOOP_TIME_S, seed=7, peak=0.35 * 386.089):
    """Synthetic earthquake-like acceleration [in/s**2]: filtered noise with an envelope.

    Band 0.2-15 Hz, Saragoni-Hart-like envelope; used where no recorded motion
    is available.  Peak scaled to ``peak`` [in/s**2].
    """
    rng = np.random.default_rng(seed)
    n = int(round(duration_s / dt))
    t = np.arange(n) * dt
    sos = scipy.signal.butter(4, [0.2, 15.0], "bandpass", fs=1.0 / dt, output="sos")
    x = scipy.signal.sosfilt(sos, rng.standard_normal(n))
    env = (t / 4.0) ** 2 * np.exp(-2.0 * (t / 4.0 - 1.0))
    x = x * np.minimum(env, 1.0)
    return t, x * peak / np.max(np.abs(x))


@pytest.fixture(scope="session")
def controller_tfs():
    return standardized_controller()


@pytest.fixture(scope="session")
def discrete(controller_tfs):
    """The standardized controller discretized at the report's loop time (Tustin)."""
    return discretize(*controller_tfs, LOOP_TIME_S, fc_hz=FC_HZ)
