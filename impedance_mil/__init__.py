"""impedance-mil: impedance-matching control design for shake-table testing and MIL simulation.

Implements the MCEER report *Impedance-Matching Control Design for
Shake-Table Testing and Model-in-the-Loop Simulations* in five phases
(Section 10.2): characterize (:mod:`.plant`, :mod:`.virtual`,
:mod:`.specimens`), design (:mod:`.design`), implement (:mod:`.implement`),
validate (:mod:`.lab`) and run campaigns (:mod:`.campaign`).

Internal units are the report's (in, lbf, s, psi, V, mA): see :mod:`.units`.
"""

__version__ = "0.1.0"

# Before any compiled kernel is loaded: numba checks a cached kernel against its own
# file only, and the loop inlines kernels of other modules (impedance_mil.kernel_cache).
from .kernel_cache import refresh_kernel_cache as _refresh_kernel_cache  # noqa: E402

_refresh_kernel_cache()
