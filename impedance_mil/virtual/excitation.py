"""Standard excitations of a VS: harmonic ground motion and a rigid test article.

Used for force-displacement loops (``imil vs loops``, report Figures 1.7b
and 9.1) without a table in the loop.
"""

from __future__ import annotations

import math

import numpy as np

from ..bounds import MAX_RECORD_SAMPLES, check_count
from ..errors import ConfigError
from .base import VirtualSystem, VSResponse


def harmonic_ground_motion(
    amplitude: float, frequency_hz: float, cycles: float = 3.0, dt: float = 0.0005, ramp_cycles: float = 0.5
) -> np.ndarray:
    """Sine ground acceleration with a raised-cosine ramp-up.

    Parameters
    ----------
    amplitude : float
        Peak ground acceleration [in/s**2].
    frequency_hz : float
        Frequency [Hz].
    cycles : float
        Number of cycles at full amplitude after the ramp.
    dt : float
        Sample period [s].
    ramp_cycles : float
        Length of the ramp, in cycles (0 for none).

    Returns
    -------
    ndarray
        a_g per sample [in/s**2].

    Raises
    ------
    ConfigError
        A non-positive or non-finite argument, or more than
        :data:`~impedance_mil.bounds.MAX_RECORD_SAMPLES` samples.
    """
    for key, value in (("amplitude", amplitude), ("frequency", frequency_hz), ("cycles", cycles), ("dt", dt)):
        if not (math.isfinite(value) and value > 0):
            raise ConfigError(key, "a positive value", value)
    if not (math.isfinite(ramp_cycles) and ramp_cycles >= 0):
        raise ConfigError("ramp_cycles", "a non-negative value", ramp_cycles)
    period = 1.0 / frequency_hz
    check_count(
        "cycles", (cycles + ramp_cycles) * period / dt, MAX_RECORD_SAMPLES, "samples (cycles x period / dt)"
    )
    n = int(round((cycles + ramp_cycles) * period / dt))
    t = np.arange(n) * dt
    ramp = np.ones(n)
    if ramp_cycles > 0:
        t_ramp = ramp_cycles * period
        inside = t < t_ramp
        ramp[inside] = 0.5 * (1.0 - np.cos(np.pi * t[inside] / t_ramp))
    return amplitude * ramp * np.sin(2.0 * np.pi * frequency_hz * t)


def rigid_article_response(vs: VirtualSystem, a_g, dt: float, m_article: float) -> VSResponse:
    """Response of a VS carrying a rigid test article of mass ``m_article``.

    The article moves with the basemat, so ``w = -m_article * z_vs``; the
    algebraic loop is solved exactly by lumping the mass on the basemat
    (:meth:`VirtualSystem.with_rigid_article`).  The returned ``w`` is that
    force [lbf]; ``z_vs`` and the isolator force are those of the lumped system.

    Parameters
    ----------
    vs : VirtualSystem
    a_g : array_like
        Ground acceleration per sample [in/s**2].
    dt : float
        Sample period [s].
    m_article : float
        Mass of the rigid article [lbf*s**2/in] (0: basemat alone).
    """
    lumped = vs.with_rigid_article(m_article)
    r = lumped.simulate(a_g, None, dt)
    w = -m_article * r.z_vs
    return VSResponse(
        time=r.time,
        a_g=r.a_g,
        w=w,
        z_vs=r.z_vs,
        displacement=r.displacement,
        velocity=r.velocity,
        force=r.force,
        f_h=r.f_h,
        final_state=r.final_state,
    )
