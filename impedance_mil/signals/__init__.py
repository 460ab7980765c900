"""Ground motions, response spectra, multisines and FRF estimation (report Sections 4.5, 8.2)."""

from .motion import GroundMotion
from .readers import BUILTIN_MOTIONS, builtin_motion, read_at2, read_columns, read_motion

__all__ = [
    "BUILTIN_MOTIONS",
    "GroundMotion",
    "builtin_motion",
    "read_at2",
    "read_columns",
    "read_motion",
]
