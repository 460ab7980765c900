"""Virtual lab: the sampled-data loop, experiments, safety limits, metrics (report Sections 4.5, 7.3, 8, 9).

>>> from impedance_mil.plant import TableParameters
>>> from impedance_mil.plant.nonlinear import NonlinearTable
>>> from impedance_mil.lab import simulate
>>> table = NonlinearTable.from_linear(TableParameters.report_default())
>>> run = simulate(table, command=[0.0] * 100)
>>> run.completed, run.n_samples
(True, 100)
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
    from .experiments import ControlledRun, FrfExperiment, KpStudy, kp_study, run_frf, run_mil, run_tracking
    from .identification import TableIdentification, identify_table, model_response
    from .loop import simulate, simulate_interface
    from .lti_plant import LTIVirtualTable, virtual_table_for
    from .metrics import RunMetrics, evaluate_run
    from .plant_interface import Measurements, PlantInterface, VirtualLTITable, VirtualTable
    from .reference import ScipyTable
    from .results import RunResult, load_run, save_run
    from .setup import SafetyLimits, default_sensors, ideal_sensors
    from .trips import Trip, TripCause

__all__ = [
    "ControlledRun",
    "FrfExperiment",
    "KpStudy",
    "LTIVirtualTable",
    "Measurements",
    "PlantInterface",
    "RunMetrics",
    "RunResult",
    "SafetyLimits",
    "ScipyTable",
    "TableIdentification",
    "Trip",
    "TripCause",
    "VirtualLTITable",
    "VirtualTable",
    "default_sensors",
    "evaluate_run",
    "identify_table",
    "ideal_sensors",
    "kp_study",
    "load_run",
    "model_response",
    "run_frf",
    "run_mil",
    "run_tracking",
    "save_run",
    "simulate",
    "simulate_interface",
    "virtual_table_for",
]

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# ``from impedance_mil.lab import RunResult`` does not import the compiled loop, design or signals.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "experiments": (
            "ControlledRun",
            "FrfExperiment",
            "KpStudy",
            "kp_study",
            "run_frf",
            "run_mil",
            "run_tracking",
        ),
        "identification": ("TableIdentification", "identify_table", "model_response"),
        "loop": ("simulate", "simulate_interface"),
        "lti_plant": ("LTIVirtualTable", "virtual_table_for"),
        "metrics": ("RunMetrics", "evaluate_run"),
        "plant_interface": ("Measurements", "PlantInterface", "VirtualLTITable", "VirtualTable"),
        "reference": ("ScipyTable",),
        "results": ("RunResult", "load_run", "save_run"),
        "setup": ("SafetyLimits", "default_sensors", "ideal_sensors"),
        "trips": ("Trip", "TripCause"),
    },
)
