"""Ground motions, response spectra, multisines and FRF estimation (report Sections 4.5, 8.2)."""

from .motion import GroundMotion
from .readers import BUILTIN_MOTIONS, builtin_motion, read_at2, read_columns, read_motion
from .spectrum import DEFAULT_PERIODS, Spectrum, oscillator_response, response_spectrum

__all__ = [
    "BUILTIN_MOTIONS",
    "DEFAULT_PERIODS",
    "GroundMotion",
    "Spectrum",
    "builtin_motion",
    "read_at2",
    "read_columns",
    "oscillator_response",
    "read_motion",
    "response_spectrum",
]
