"""The stages of a loop tick against a plant interface and a runtime, in Python.

The Python *stage namespace* of :func:`impedance_mil.lab.tick.sequence`: the
same names as the compiled stages of :mod:`impedance_mil.lab.kernels`, with
the plant a :class:`~impedance_mil.lab.plant_interface.PlantInterface`
(:class:`~impedance_mil.lab.plant_interface.VirtualTable`, the solve_ivp
reference, a link to a real controller) and ``control.controller`` a
:class:`~impedance_mil.implement.MILRuntime` (or None in open loop), which
steps its own VS -- compiled, or a user-defined one in Python.
"""

from __future__ import annotations

import math

from ..errors import LimitTripped
from .structures import PlantTruth, record_loop
from .trips import TripCause

#: Stage "record": the same function as the compiled loop's.
record = record_loop


def read(plant, k):
    """Stages 1-2, sense and safety: ``(Measurements, TripCause, value)``; ``m`` None after a trip.

    The plant senses and checks its interlocks in ``read_sensors``, which raises
    :class:`~impedance_mil.errors.LimitTripped`.
    """
    try:
        return plant.read_sensors(), TripCause.NONE, 0.0
    except LimitTripped as exc:
        return None, exc.cause, math.nan if exc.value is None else float(exc.value)


def record_vs_state(log, k, control):
    """Record the runtime's VS state at the start of loop ``k`` (nothing without a runtime)."""
    runtime = control.controller
    if runtime is not None:
        log.vs_states[k, :] = runtime.x_vs


def track_step(control, a_g, w):
    """Stage 3, tracking: ``(u, u_w)`` [in] from ``z_vs = a_g`` [in/s^2] and ``w`` [lbf]."""
    return control.controller.step_parts(a_g, w)


def mil_step(control, vs_tick, a_g, w):
    """Stage 3, MIL: ``(u [in], z_vs [in/s^2], u_w [in])``; the runtime steps its own VS (``vs_tick`` unused)."""
    out = control.controller.mil_step(a_g, w)
    return out.u, out.z_vs, out.u_w


def command(plant, m, u):
    """Stage 4: the position command ``u`` [in] of this loop."""
    plant.write_command(u)


def truth(plant) -> PlantTruth:
    """The plant's true quantities of this loop (its ``truth()``), NaN for those it does not offer."""
    known = plant.truth() if hasattr(plant, "truth") else {}
    return PlantTruth(*(known.get(name, math.nan) for name in PlantTruth._fields))


def advance(plant):
    """Stage 5: let one loop time pass."""
    plant.advance()
