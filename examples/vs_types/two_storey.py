"""A virtual system of your own: an isolated two-storey frame with the test article on its roof.

This file is a user-defined VS type, written the way the built-in ones are
(``impedance_mil/virtual/types/*.py``).  Use it with any command that takes
``--vs``::

    imil simulate --vs examples/vs_types/two_storey.py --pga 0.3 -o frame.h5
    imil export design.json --format c -o out/     # after imil design --vs ...two_storey.py

or from a VS file (TOML) that names it and sets its parameters::

    type_file = "two_storey.py"
    m_vs = "2000 lb"
    k_b = "600 lbf/in"
    ...

Model (displacements relative to the ground: base slab u_b, first floor u_1,
roof u_2; velocities v = du/dt)::

    m_b  dv_b/dt = f_1 - f_b  - m_b a_g       f_b = k_b u_b + c_b v_b               (isolators)
    m_1  dv_1/dt = f_2 - f_1  - m_1 a_g       f_1 = k_1 (u_1 - u_b) + c_1 (v_1 - v_b) (storey 1)
    m_vs dv_2/dt = w   - f_2  - m_vs a_g      f_2 = k_2 (u_2 - u_1) + c_2 (v_2 - v_1) (storey 2)

The table imitates the roof's absolute acceleration ``z_vs = (w - f_2)/m_vs``.
The system is linear (no nonlinear input), so its linear part is exact and
the design needs no equivalent linearization.
"""

from __future__ import annotations

import math

import numpy as np

from impedance_mil.units import G0, INTERNAL_UNITS, TWO_PI
from impedance_mil.virtual import DefinedVS, Parameter, VSDefinition, VSType

_MASS = INTERNAL_UNITS["mass"]
_K = "force_pound / inch"
_C = "force_pound * second / inch"

DEFINITION = VSDefinition(
    kind="ISO2",
    title="base-isolated two-storey frame, test article on the roof",
    source="examples/vs_types/two_storey.py (shear-building model)",
    parameters=(
        Parameter("m_vs", _MASS, "Roof mass"),
        Parameter("m_b", _MASS, "Base-slab mass"),
        Parameter("m_1", _MASS, "First-floor mass"),
        Parameter("k_b", _K, "Isolator stiffness"),
        Parameter("c_b", _C, "Isolator damping", "nonnegative"),
        Parameter("k_1", _K, "First-storey stiffness"),
        Parameter("c_1", _C, "First-storey damping", "nonnegative"),
        Parameter("k_2", _K, "Second-storey stiffness"),
        Parameter("c_2", _C, "Second-storey damping", "nonnegative"),
    ),
    states=("u_b", "u_1", "u_2", "v_b", "v_1", "v_2"),
    state_units=("inch",) * 3 + ("inch / second",) * 3,
    intermediates=(
        ("f_b", "k_b*u_b + c_b*v_b"),
        ("f_1", "k_1*(u_1 - u_b) + c_1*(v_1 - v_b)"),
        ("f_2", "k_2*(u_2 - u_1) + c_2*(v_2 - v_1)"),
    ),
    rates={
        "u_b": "v_b",
        "u_1": "v_1",
        "u_2": "v_2",
        "v_b": "(f_1 - f_b)/m_b - a_g",
        "v_1": "(f_2 - f_1)/m_1 - a_g",
        "v_2": "(w - f_2)/m_vs - a_g",
    },
    outputs={"z_vs": "(w - f_2)/m_vs", "displacement": "u_2", "velocity": "v_2", "force": "f_b"},
    reference={
        "m_vs": 5.18,
        "m_b": 5.18,
        "m_1": 5.18,
        "k_b": 600.0,
        "c_b": 40.0,
        "k_1": 1e4,
        "c_1": 10.0,
        "k_2": 1e4,
        "c_2": 10.0,
    },
)


def example_two_storey(
    isolation_period: float = 2.0,
    isolation_damping: float = 0.15,
    storey_frequency: float = 5.0,
    storey_damping: float = 0.02,
    floor_weight: float = 2000.0,
    w_ps: float = 3600.0,
) -> DefinedVS:
    """A plausible isolated two-storey frame sized like the report's systems.

    Parameters
    ----------
    isolation_period : float
        Period of the whole building plus article on the isolators [s].
    isolation_damping : float
        Damping ratio of that isolation mode.
    storey_frequency : float
        Fixed-base frequency of a single storey carrying one floor [Hz].
    storey_damping : float
        Damping ratio of that storey.
    floor_weight : float
        Weight of each of the three slabs (base, floor 1, roof) [lbf].
    w_ps : float
        Weight of the test article on the roof [lbf] (used for sizing only).
    """
    m = floor_weight / G0
    total = 3.0 * m + w_ps / G0
    k_b = (TWO_PI / isolation_period) ** 2 * total
    k_s = (TWO_PI * storey_frequency) ** 2 * (m + w_ps / G0)
    c_s = 2.0 * storey_damping * math.sqrt(k_s * (m + w_ps / G0))
    return DefinedVS(
        DEFINITION,
        {
            "m_vs": m,
            "m_b": m,
            "m_1": m,
            "k_b": k_b,
            "c_b": 2.0 * isolation_damping * math.sqrt(k_b * total),
            "k_1": k_s,
            "c_1": c_s,
            "k_2": k_s,
            "c_2": c_s,
        },
    )


def modes(vs: DefinedVS) -> list[tuple[float, float]]:
    """(frequency [Hz], damping ratio) of each mode of the frame alone, lowest first."""
    A = np.array([vs.derivative(np.eye(6)[j], 0.0, 0.0) for j in range(6)]).T  # linear: exact columns
    poles = np.linalg.eigvals(A)
    poles = poles[poles.imag > 0]
    return sorted((abs(p) / TWO_PI, -p.real / abs(p)) for p in poles)


TYPE = VSType(DEFINITION, presets={"ISO2": example_two_storey().parameters})
