"""Optimization-based MIL controller design with certified, robust passivity (report Section 10.4).

>>> from impedance_mil.design.optimized import PoleBasis
>>> PoleBasis.butterworth_groups([80.0]).n_w   # b_0, one real pole, one pair (2 terms)
4

See :func:`design_optimized` and docs/design.md, "Optimized design".
"""

from .amplitudes import AmplitudeCertificate, amplitude_certificate, with_amplitude_certificate
from .basis import DEFAULT_GROUPS_HZ, PoleBasis, butterworth_poles, default_basis
from .certify import Certificate, certify
from .design import design_optimized
from .indices import passivity_index, sampled_margin_deg, with_indices
from .problem import MISSING_SOLVER, OptimizationSettings

__all__ = [
    "AmplitudeCertificate",
    "amplitude_certificate",
    "with_amplitude_certificate",
    "DEFAULT_GROUPS_HZ",
    "MISSING_SOLVER",
    "Certificate",
    "OptimizationSettings",
    "PoleBasis",
    "butterworth_poles",
    "certify",
    "default_basis",
    "design_optimized",
    "passivity_index",
    "sampled_margin_deg",
    "with_indices",
]
