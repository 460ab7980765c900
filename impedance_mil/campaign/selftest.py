"""The ``selftest`` campaign kind: a small, exact numeric job for checking the engine.

It computes the modes of a single-degree-of-freedom isolator (the spring-damper
virtual system of the report, Section 5.3, Equation 5-2a's denominator
``m s**2 + c s + k``) from its mass, stiffness and damping, and writes them
to an HDF5 file.  It lets a lab engineer check a Dask cluster or a worker
pool end to end (``imil campaign run selftest --scheduler tcp://...``) without
the virtual lab, and it lets the tests exercise failures and interruptions
(``fail`` and ``delay`` parameters).
"""

from __future__ import annotations

import math
import os
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from ..errors import ConfigError, ImilError
from ..units import INTERNAL_UNITS, TWO_PI
from .params import Param

#: Parameters of the ``selftest`` kind.
SELFTEST_PARAMS: dict[str, Param] = {
    "mass": Param(
        "oscillator.mass",
        unit=INTERNAL_UNITS["mass"],
        check="positive",
        help="total mass on the isolator, m_vs + m_ps [lbf*s^2/in]",
    ),
    "stiffness": Param(
        "oscillator.stiffness",
        unit="force_pound / inch",
        check="positive",
        help="horizontal stiffness k_s [lbf/in]",
    ),
    "damping": Param(
        "oscillator.damping",
        unit="force_pound * second / inch",
        check="nonnegative",
        help="viscous damping coefficient c [lbf*s/in]",
    ),
    "delay": Param(
        "delay",
        unit="second",
        check="nonnegative",
        help="wall-clock time the run sleeps before returning [s] (engine tests)",
    ),
    "fail": Param("fail", type="boolean", help="raise an error instead of computing (engine tests)"),
}

#: Default configuration of the ``selftest`` kind: SD2 of Table 9.1 (5600 lb on 894 lbf/in, 57 lbf*s/in).
SELFTEST_DEFAULTS: dict[str, Any] = {
    "oscillator": {"mass": 5600.0 / 386.08858267716535, "stiffness": 894.0, "damping": 57.0},
    "delay": 0.0,
    "fail": False,
}


class SelftestFailure(ImilError, RuntimeError):
    """The failure a ``selftest`` run raises on request (``fail = true``)."""


def run_selftest(config: dict[str, Any], out_path: Path) -> dict[str, float]:
    """Modes of ``m s**2 + c s + k`` (report Eq. 5-2a denominator), written to HDF5.

    Parameters
    ----------
    config : dict
        ``oscillator.mass`` [lbf*s^2/in], ``oscillator.stiffness`` [lbf/in],
        ``oscillator.damping`` [lbf*s/in], ``delay`` [s], ``fail`` (bool).
    out_path : Path
        HDF5 file to write (the poles, in rad/s).

    Returns
    -------
    dict
        ``frequency_hz`` (undamped natural frequency [Hz]), ``damping_ratio`` [-],
        ``period_s`` [s], ``max_pole_real`` [rad/s] and ``worker_pid``.

    Raises
    ------
    SelftestFailure
        When ``fail`` is true.
    """
    osc = config["oscillator"]
    m, k, c = float(osc["mass"]), float(osc["stiffness"]), float(osc["damping"])
    if not (m > 0 and k > 0 and c >= 0):
        raise ConfigError("oscillator", "mass > 0, stiffness > 0, damping >= 0", osc)
    time.sleep(float(config.get("delay", 0.0)))
    if config.get("fail", False):
        raise SelftestFailure("selftest run failed on request (fail = true)")
    poles = np.roots([m, c, k])
    omega_n = math.sqrt(k / m)
    with h5py.File(out_path, "w") as fh:
        fh.create_dataset("poles_real", data=poles.real)
        fh.create_dataset("poles_imag", data=poles.imag)
        fh.attrs["units"] = "rad/s"
    return {
        "frequency_hz": omega_n / TWO_PI,
        "damping_ratio": c / (2.0 * math.sqrt(k * m)),
        "period_s": TWO_PI / omega_n,
        "max_pole_real": float(np.max(poles.real)),
        "worker_pid": float(os.getpid()),
    }
