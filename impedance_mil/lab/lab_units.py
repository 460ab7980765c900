"""The unit of every numeric value of a lab's JSON (:meth:`LabSetup.to_dict`), in internal units.

Its own module so that what only needs the units (the JSON ``units`` block of any command,
:mod:`impedance_mil.report.documents`) does not import the lab-file reader
(:mod:`impedance_mil.lab.labfile`, which re-exports :data:`LAB_UNITS`): issue 16, start-up.
"""

from __future__ import annotations

from ..plant.table_dynamics import DYNAMICS_UNITS

#: Unit of every numeric value of :meth:`~impedance_mil.lab.labfile.LabSetup.to_dict` (internal units).
LAB_UNITS = {
    "limits.stroke": "in",
    "limits.velocity": "in/s",
    "limits.acceleration": "in/s**2",
    "limits.actuator_force": "lbf",
    "limits.pressure": "psi",
    "limits.valve_command": "V",
    "limits.valve_current": "mA",
    "limits.valve_duty": "",
    "limits.valve_saturation_time": "s",
    "limits.command_slew": "V/s",
    "limits.interlock_window": "s",
    "limits.divergence": "in",
    "limits.hf_cutoff": "Hz",
    "limits.hf_window": "s",
    "limits.hf_growth": "",
    "limits.hf_windows": "",
    "limits.hf_floor": "in/s**2",
    "sensors.channels.range": "unit of the channel",
    "sensors.channels.bandwidth": "Hz",
    "controller.loop_time": "s",
    "controller.output_delay": "loops",
    "controller.adc_range": "V",
    "controller.dac_range": "V",
    "specimen.water_depth": "in",
    "specimen.article_weight": "lbf",
    "dynamics.platen.modal_mass": "lbf*s**2/in",
    "dynamics.platen.frequency": "Hz",
    "dynamics.platen.damping": "",
    "dynamics.load_cells.stiffness": "lbf/in",
    "dynamics.load_cells.damping_ratio": "",
    "dynamics.load_cells.damping_coefficient": "lbf*s/in",
    "dynamics.load_cells.base_mass": "lbf*s**2/in",
    "table": "see imil table info",
    **{f"dynamics.{k}": v for k, v in DYNAMICS_UNITS.items()},
}

#: Paths of :meth:`~impedance_mil.lab.labfile.LabSetup.to_dict` that hold an optional section, an
#: object (null when the lab has none): no number, so the JSON ``units`` block needs no registry
#: to name them (tests/lab/test_labfile.py holds this list to the document).
LAB_OBJECTS = frozenset({"uncertainty", "calibration", "dynamics.platen", "dynamics.load_cells"})
