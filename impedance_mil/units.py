"""The one internal unit system of impedance-mil, and its constants.

Every number inside the library is in the report's units (MCEER report,
Table 4.1 and Sections 3-9):

================  =====================  ==========================================
quantity          internal unit          note
================  =====================  ==========================================
length            in
time              s
force             lbf
mass              lbf*s**2/in            1 lbf*s**2/in = 386.089 lb (mass)
pressure          psi = lbf/in**2
voltage           V
current           mA
flow              in**3/s
frequency         Hz at every interface  rad/s only inside transfer functions
acceleration      in/s**2                ground motions in g only at the edges
================  =====================  ==========================================

Conversion happens only at the edges: :mod:`impedance_mil.config` turns
quantities with units (pint strings such as ``"1600 lb"`` or ``"2.1 in**2"``)
into these units, and the CLI and report modules convert accelerations to g
for display.  A bare number in a configuration file means the report's unit
of that key.

In pint, ``g`` means gram; the standard gravity is spelled ``g0`` in our
configuration files (see :data:`PINT_DEFINITIONS`).
"""

from __future__ import annotations

import math

#: Standard gravity [in/s**2] (9.80665 m/s**2 / 0.0254 m/in).
G0: float = 9.80665 / 0.0254

#: Angular frequency per Hz [rad/s per Hz].
TWO_PI: float = 2.0 * math.pi

#: Internal unit of each physical dimension, as pint unit expressions.
INTERNAL_UNITS: dict[str, str] = {
    "length": "inch",
    "time": "second",
    "force": "force_pound",
    "mass": "force_pound * second**2 / inch",
    "pressure": "psi",
    "voltage": "volt",
    "current": "milliampere",
    "flow": "inch**3 / second",
    "frequency": "hertz",
    "acceleration": "inch / second**2",
    "velocity": "inch / second",
    "area": "inch**2",
    "stiffness": "force_pound / inch",
    "damping": "force_pound * second / inch",
    "dimensionless": "dimensionless",
}

#: Extra pint definitions loaded by :mod:`impedance_mil.config`:
#: ``g0`` is standard gravity (pint's ``g`` is the gram).
PINT_DEFINITIONS: tuple[str, ...] = ("g0 = 9.80665 * meter / second ** 2",)


def weight_to_mass(weight_lbf: float) -> float:
    """Mass [lbf*s**2/in] of a body of the given weight [lbf]."""
    return weight_lbf / G0


def g_to_in_s2(acc_g: float):
    """Convert an acceleration [g] to [in/s**2] (works on arrays)."""
    return acc_g * G0


def in_s2_to_g(acc):
    """Convert an acceleration [in/s**2] to [g] (works on arrays)."""
    return acc / G0
