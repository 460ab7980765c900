"""Force-displacement loops of virtual systems carrying a rigid article (report Figure 9.1, ``imil vs loops``).

:func:`vs_loops` drives each VS with a harmonic ground acceleration or a
recorded motion, the article lumped on the basemat
(:func:`impedance_mil.virtual.excitation.rigid_article_response`), and
returns the responses with their peaks, the energy each isolator dissipates
and its axial load.  The article's weight is the VS's own design weight
(``w_ps`` of its targets) unless given, else the report's article
(``[specimen] article_weight`` of the report's setup).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..bounds import MAX_RECORD_SAMPLES, check_count
from ..report_config import report_config
from ..signals import GroundMotion
from ..units import G0, weight_to_mass
from ..virtual import VSResponse
from ..virtual.excitation import harmonic_ground_motion, rigid_article_response
from ..virtual.files import VSSpec
from .metrics import dissipated_energy


@dataclass(frozen=True, eq=False)
class LoopInput:
    """A ground acceleration per step [in/s^2], its step [s] and a description."""

    a_g: np.ndarray
    dt: float
    text: str


def harmonic_input(amplitude: float, frequency_hz: float, cycles: float, dt: float) -> LoopInput:
    """A ramped sine of ``amplitude`` [in/s^2] at ``frequency_hz`` [Hz], ``cycles`` at full amplitude, step ``dt`` [s]."""
    a_g = harmonic_ground_motion(amplitude, frequency_hz, cycles, dt)
    return LoopInput(a_g, dt, f"{amplitude / G0:.3g} g at {frequency_hz:.3g} Hz")


def recorded_input(motion: GroundMotion, dt: float, label: str = "") -> LoopInput:
    """A recorded motion held over as many steps of at most ``dt`` [s] as fit in its sample interval."""
    substeps = max(1, math.ceil(motion.time_step / dt - 1e-9))
    check_count("dt", motion.npts * substeps, MAX_RECORD_SAMPLES, "samples (record x steps per sample)")
    a_g = np.repeat(motion.accel, substeps)  # held over each record sample
    return LoopInput(a_g, motion.time_step / substeps, f"{motion.name or label}, {substeps} steps per sample")


def article_weight(spec: VSSpec) -> float:
    """The weight [lbf] of the rigid article a VS is designed for (its ``w_ps``), else the report's article."""
    for source in (spec.vs, spec.targets):
        if source is not None and hasattr(source, "w_ps"):
            return float(source.w_ps)
    return report_config().specimen.article_weight_lbf


@dataclass(frozen=True, eq=False)
class VSLoop:
    """One VS's response and its summary (peaks in in, lbf, in/s^2; energy in lbf*in; axial load in lbf)."""

    spec: VSSpec
    response: VSResponse
    axial_load: float

    def summary(self) -> dict:
        r = self.response
        return {
            "name": self.spec.name,
            "kind": self.spec.vs.kind,
            "peak_displacement": float(np.abs(r.displacement).max()),
            "peak_force": float(np.abs(r.force).max()),
            "peak_z_vs": float(np.abs(r.z_vs).max()),
            "dissipated_energy": dissipated_energy(r.force, r.displacement),
            "axial_load": self.axial_load,
        }


def vs_loops(specs: Sequence[VSSpec], loop_input: LoopInput, weight_lbf: float | None = None) -> list[VSLoop]:
    """Each VS under ``loop_input`` with a rigid article of ``weight_lbf`` [lbf] (None: :func:`article_weight`)."""
    loops = []
    for spec in specs:
        weight = article_weight(spec) if weight_lbf is None else weight_lbf
        m_article = weight_to_mass(weight)
        r = rigid_article_response(spec.vs, loop_input.a_g, loop_input.dt, m_article)
        loops.append(VSLoop(spec, r, spec.vs.m_vs * G0 + m_article * G0))
    return loops
