"""Virtual lab: the sampled-data loop, experiments, safety limits, metrics (report Sections 4.5, 7.3, 8, 9).

>>> from impedance_mil.plant import TableParameters
>>> from impedance_mil.plant.nonlinear import NonlinearTable
>>> from impedance_mil.lab import simulate
>>> table = NonlinearTable.from_linear(TableParameters.report_default())
>>> run = simulate(table, command=[0.0] * 100)
>>> run.completed, run.n_samples
(True, 100)
"""

from .experiments import ControlledRun, FrfExperiment, KpStudy, kp_study, run_frf, run_mil, run_tracking
from .identification import TableIdentification, identify_table, model_response
from .loop import simulate, simulate_interface
from .metrics import RunMetrics, evaluate_run
from .plant_interface import Measurements, PlantInterface, VirtualTable
from .reference import ScipyTable
from .results import RunResult, load_run, save_run
from .setup import SafetyLimits, default_sensors, ideal_sensors
from .trips import Trip, TripCause

__all__ = [
    "ControlledRun",
    "FrfExperiment",
    "KpStudy",
    "Measurements",
    "PlantInterface",
    "RunMetrics",
    "RunResult",
    "SafetyLimits",
    "ScipyTable",
    "TableIdentification",
    "Trip",
    "TripCause",
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
]
