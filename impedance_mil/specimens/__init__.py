"""Test articles (rigid mass, MDOF, fluid-filled vessel) and sensors (report Sections 3.2, 3.5, 7.2).

Every specimen maps the absolute table acceleration ``z`` [in/s**2] to the
interface force ``w`` [lbf] it applies on the table (report Eq 4-7b:
``m_st * z = A_p * dP + w``; a rigid mass ``m`` gives ``w = -m z``).
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
    from . import sensors
    from .factory import specimen_from_config, specimen_from_dict
    from .statespace import SpecimenStateSpace, rk4_step
    from .structural import LinearMDOF, ModalProperties, RigidMass, Specimen, modal_damping_matrix
    from .vessel import FluidVessel, Oscillator

__all__ = [
    "FluidVessel",
    "LinearMDOF",
    "ModalProperties",
    "Oscillator",
    "RigidMass",
    "Specimen",
    "SpecimenStateSpace",
    "modal_damping_matrix",
    "rk4_step",
    "sensors",
    "specimen_from_config",
    "specimen_from_dict",
]

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# a specimen's names do not import every specimen module.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "factory": ("specimen_from_config", "specimen_from_dict"),
        "statespace": ("SpecimenStateSpace", "rk4_step"),
        "structural": ("LinearMDOF", "ModalProperties", "RigidMass", "Specimen", "modal_damping_matrix"),
        "vessel": ("FluidVessel", "Oscillator"),
    },
    submodules=("sensors",),
)
