"""impedance-mil: impedance-matching control design for shake-table testing and MIL simulation.

Implements the MCEER report *Impedance-Matching Control Design for
Shake-Table Testing and Model-in-the-Loop Simulations* in five phases
(Section 10.2): characterize (:mod:`.plant`, :mod:`.virtual`,
:mod:`.specimens`), design (:mod:`.design`), implement (:mod:`.implement`),
validate (:mod:`.lab`) and run campaigns (:mod:`.campaign`).

Internal units are the report's (in, lbf, s, psi, V, mA): see :mod:`.units`.
"""

__version__ = "0.1.0"
