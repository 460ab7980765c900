"""Ground motions, response spectra, multisines and FRF estimation (report Sections 4.5, 8.2)."""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
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

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# ``from impedance_mil.signals import GroundMotion`` does not import pandas, h5py or numba.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "fema": ("FEMA_RECORD_SETS", "fema_available", "read_fema_p695"),
        "limits": ("LimitCheck", "MotionCheck", "TableLimits", "check_motion", "required_rated_flow"),
        "motion": ("GroundMotion",),
        "readers": (
            "BUILTIN_MOTIONS",
            "builtin_motion",
            "read_at2",
            "read_columns",
            "read_motion",
            "write_columns",
        ),
        "spectrum": (
            "DEFAULT_PERIODS",
            "Spectrum",
            "log_periods",
            "oscillator_response",
            "response_spectrum",
        ),
    },
)
