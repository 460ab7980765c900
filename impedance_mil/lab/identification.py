"""Identification of the table's system parameters from a measured FRF (report Sections 4.3.5, 4.5).

The report determines ``omega_oil``, ``zeta_oil`` and ``d`` "by comparing the
frequency responses of the model and the table measurements"; here they are
fitted with :func:`impedance_mil.signals.frf.fit_frf` (least squares on
log-magnitude and phase) to a measured FRF such as ``z/u`` of the bare table,
optionally with the two servovalve poles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..plant import LinearTable, TableParameters
from ..signals.frf import FRF, FitResult, fit_frf

#: Parameters that can be identified (TableParameters fields, plus the valve poles).
IDENTIFIABLE = (
    "f_oil_hz",
    "zeta_oil",
    "d",
    "valve_pole_1_hz",
    "valve_pole_2_hz",
    "valve_time_constant",
    "valve_frequency_hz",
    "valve_damping",
)
#: The valve parameters of each valve kind that can be identified (plant.parameters.VALVE_KINDS).
VALVE_IDENTIFIABLE = {
    "two-pole": ("valve_pole_1_hz", "valve_pole_2_hz"),
    "first-order": ("valve_time_constant",),
    "second-order": ("valve_frequency_hz", "valve_damping"),
}
_DIRECT = ("f_oil_hz", "zeta_oil", "d", "valve_time_constant", "valve_frequency_hz", "valve_damping")


def _with(p0: TableParameters, values: dict) -> TableParameters:
    changes = {k: v for k, v in values.items() if k in _DIRECT}
    if p0.valve != "two-pole":
        return p0.replace(**changes)
    poles = list(p0.valve_poles_hz)
    if "valve_pole_1_hz" in values:
        poles[0] = values["valve_pole_1_hz"]
    if "valve_pole_2_hz" in values:
        poles[1] = values["valve_pole_2_hz"]
    return p0.replace(valve_poles_hz=tuple(poles), **changes)


def _start(p: TableParameters) -> dict[str, float]:
    """Starting values of the identifiable parameters of ``p`` (its valve kind's only)."""
    start = {"f_oil_hz": p.f_oil_hz, "zeta_oil": p.zeta_oil, "d": p.d}
    if p.valve == "two-pole":
        start |= {"valve_pole_1_hz": p.valve_poles_hz[0], "valve_pole_2_hz": p.valve_poles_hz[1]}
    for name in VALVE_IDENTIFIABLE.get(p.valve, ()):
        if name in _DIRECT:
            start[name] = float(getattr(p, name))
    return start


def model_response(
    p: TableParameters, output: str, f_hz, delay: str = "first-order", input: str = "u"
) -> np.ndarray:
    """Linear-model response ``output/input`` at ``f_hz`` [Hz] for a delay treatment."""
    table = LinearTable(p, delay=delay)
    if delay == "sampled":
        return table.sampled().frequency_response(output, input, f_hz)
    return table.state_space().frequency_response(output, input, f_hz)


@dataclass(frozen=True)
class TableIdentification:
    """Identified table parameters.

    Attributes
    ----------
    parameters : TableParameters
        The starting parameters with the identified values.
    initial : TableParameters
        Starting parameters.
    fit : FitResult
        Optimizer outcome (``rms_log_error``: misfit of the linear model).
    output : str
        Output of the fitted FRF (``"z"``, ``"x"`` or ``"dp"``).
    delay : str
        Delay treatment of the linear model fitted.
    """

    parameters: TableParameters
    initial: TableParameters
    fit: FitResult
    output: str
    delay: str

    @property
    def rms_log_error(self) -> float:
        """RMS misfit ``|log(H_model/H_meas)|`` over the fitted lines (dimensionless)."""
        return self.fit.rms_log_error

    def intervals(self, z: float = 1.96) -> dict[str, tuple[float, float]]:
        """95 % confidence interval (``z`` = 1.96) of each identified parameter, from the fit's Jacobian."""
        if self.fit.log_covariance is None:
            return {}
        return {name: self.fit.confidence_interval(name, z) for name in self.fit.free}

    def summary(self) -> dict:
        """Identified values: oil-column frequency [Hz] and damping, d, valve poles [Hz]."""
        p = self.parameters
        return {
            "f_oil_hz": p.f_oil_hz,
            "zeta_oil": p.zeta_oil,
            "d": p.d,
            "valve_poles_hz": tuple(p.valve_poles_hz),
            "rms_log_error": self.rms_log_error,
        }


def identify_table(
    frf: FRF,
    initial: TableParameters,
    *,
    output: str = "z",
    free=("f_oil_hz", "zeta_oil", "d"),
    delay: str = "first-order",
    f_range_hz: tuple[float, float] = (0.25, 100.0),
    coherence_weighting: bool = True,
    weights=None,
) -> TableIdentification:
    """Fit the linear model's system parameters to a measured FRF of the bare table.

    Parameters
    ----------
    frf : FRF
        Measured ``output/u`` FRF (u: position command [in]).
    initial : TableParameters
        Starting values; control parameters (K_e, K_p, K_v, tau_s) and the
        specification parameters are kept.
    output : {"z", "x", "dp"}
        Output of the FRF.
    free : sequence of str
        Parameters to identify, from ``IDENTIFIABLE``.
    delay : {"none", "first-order", "pade", "sampled"}
        Delay treatment of the fitted linear model (report: first-order).
    f_range_hz : (float, float)
        Band of the fit [Hz].
    coherence_weighting : bool
        Weight lines by coherence (see :func:`fit_frf`).
    weights : array_like, optional
        Weight of each line in the band instead (``sqrt(2) |H| / std``, see :func:`fit_frf`).

    Returns
    -------
    TableIdentification
    """
    unknown = [name for name in free if name not in IDENTIFIABLE]
    if unknown:
        raise ConfigError("identify.free", "names from " + ", ".join(IDENTIFIABLE), unknown)
    start = _start(initial)
    other_valve = [name for name in free if name not in start]
    if other_valve:
        raise ConfigError(
            "identify.free",
            f"parameters of this table's {initial.valve} valve: " + ", ".join(start),
            other_valve,
        )

    def model(values, f_hz):
        return model_response(_with(initial, values), output, f_hz, delay)

    fit = fit_frf(
        frf,
        model,
        start,
        free=list(free),
        f_range_hz=f_range_hz,
        coherence_weighting=coherence_weighting,
        weights=weights,
    )
    return TableIdentification(
        parameters=_with(initial, fit.parameters), initial=initial, fit=fit, output=output, delay=delay
    )
