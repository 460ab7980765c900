"""Model-only campaign kinds: ``table-poles`` (Section 4.4) and ``design`` (Sections 6, 9.4).

Both evaluate the linear models, with no time simulation, so a sweep of
hundreds of parameter sets takes seconds:

* ``table-poles``: closed-loop poles of the controlled table
  (:class:`impedance_mil.plant.LinearTable`) for K_e, K_p, loop time and
  delay treatment: the tuning studies of Section 4.4;
* ``design``: the filtered MIL controller for a VS preset, basemat mass and
  cut-off, and its constraints I, II, III (Section 9.4.3, Table 9.5; the
  basemat-mass study of Section 9.4.4).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import h5py
import numpy as np

from ..design import design_controller, table_model, virtual_model
from ..design.forms import FORMS
from ..design.io import save_design
from ..plant import DELAYS, LinearTable, TableParameters
from ..report_config import report_config
from ..units import INTERNAL_UNITS, TWO_PI
from ..virtual import presets
from .params import Param

#: Table parameters shared by every kind that models the table (Table 4.1 keys).
TABLE_PARAMS: dict[str, Param] = {
    "K_e": Param("table.Ke", unit="volt / inch", check="positive", help="proportional gain K_e [V/in]"),
    "K_p": Param("table.Kp", unit="volt / psi", check="nonnegative", help="Delta-P gain K_p [V/psi]"),
    "loop_time": Param(
        "table.loop_time", unit="second", check="nonnegative", help="controller loop time tau_s [s]"
    ),
    "m_st": Param(
        "table.mass",
        unit=INTERNAL_UNITS["mass"],
        check="positive",
        help="moving table mass m_st [lbf*s^2/in]",
    ),
}

#: Virtual-system parameters shared by the design and MIL kinds.
VS_PARAMS: dict[str, Param] = {
    "vs": Param(
        "vs.preset", type="choice", choices=presets.names(), help="isolation system of Tables 9.1-9.3"
    ),
    "m_vs_ratio": Param(
        "vs.m_vs_ratio",
        unit="dimensionless",
        check="positive",
        help="basemat mass as a multiple of the table mass, m_vs/m_st (Section 9.4.4)",
    ),
}

#: Controller parameters shared by the design, tracking and MIL kinds.
CONTROLLER_PARAMS: dict[str, Param] = {
    "f_c": Param("controller.fc_hz", unit="hertz", check="positive", help="filter cut-off f_c [Hz]"),
}


def table_parameters(config: dict[str, Any]) -> TableParameters:
    """Table 4.1 with the ``table`` entries of a run configuration replaced (internal units)."""
    changes = {k: v for k, v in config.get("table", {}).items() if v is not None}
    return TableParameters.report_default().replace(**changes)


def virtual_system(config: dict[str, Any], table_mass: float):
    """The VS preset of a run configuration.

    Its basemat mass is ``m_vs_ratio * m_st`` when the ratio is given, else
    ``m_vs`` [lbf*s^2/in] when given, else the preset's (Tables 9.1-9.3).
    """
    vs = config["vs"]
    if vs.get("m_vs_ratio") is not None:
        return presets.get(vs["preset"], m_vs=float(vs["m_vs_ratio"]) * table_mass)
    if vs.get("m_vs") is not None:
        return presets.get(vs["preset"], m_vs=float(vs["m_vs"]))
    return presets.get(vs["preset"])


# ---------------------------------------------------------------- table-poles
TABLE_POLES_PARAMS: dict[str, Param] = {
    **TABLE_PARAMS,
    "delay": Param("delay", type="choice", choices=DELAYS, help="treatment of the loop delay"),
}
TABLE_POLES_DEFAULTS: dict[str, Any] = {"table": {}, "delay": "first-order"}


def run_table_poles(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Closed-loop poles of the controlled table (report Eq 4-14, Section 4.4).

    Returns
    -------
    dict
        ``stable``; ``max_pole_real`` [rad/s]; ``oil_frequency_hz`` [Hz] and
        ``oil_damping_ratio`` [-] of the least-damped complex pole pair.
    """
    params = table_parameters(config)
    poles = np.asarray(LinearTable(params, delay=config["delay"]).poles())
    with h5py.File(out_path, "w") as fh:
        fh.create_dataset("poles_real", data=poles.real)
        fh.create_dataset("poles_imag", data=poles.imag)
        fh.attrs["units"] = "rad/s"
    complex_poles = poles[poles.imag > 1e-9]
    out: dict[str, Any] = {"stable": bool(np.all(poles.real < 0)), "max_pole_real": float(np.max(poles.real))}
    if complex_poles.size:
        zeta = -complex_poles.real / np.abs(complex_poles)
        k = int(np.argmin(zeta))
        out["oil_frequency_hz"] = float(np.abs(complex_poles[k]) / TWO_PI)
        out["oil_damping_ratio"] = float(zeta[k])
    return out


# --------------------------------------------------------------------- design
DESIGN_PARAMS: dict[str, Param] = {
    **TABLE_PARAMS,
    **VS_PARAMS,
    **CONTROLLER_PARAMS,
    "form": Param(
        "controller.form",
        type="choice",
        choices=tuple(FORMS),
        help="controller form (Section 6): standardized, vs-specific, tracking, general",
    ),
}
#: The report's VS, cut-off and form (``report_config``); m_vs/m_st = 1.25 is SD2's 2000 lb basemat
#: on the 1600 lb table (Table 9.1), the start of the basemat-mass study of Section 9.4.4.
DESIGN_DEFAULTS: dict[str, Any] = {
    "table": {},
    "vs": {"preset": report_config().vs_preset, "m_vs_ratio": 1.25},
    "controller": {"fc_hz": report_config().design.fc_hz, "form": report_config().design.form},
}


def run_design(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Design the filtered MIL controller and evaluate constraints I, II, III (Section 9.4).

    Writes the design file (:func:`impedance_mil.design.io.save_design`; it
    can be loaded, exported and simulated) to ``out_path``.

    Returns
    -------
    dict
        The :class:`~impedance_mil.design.ConstraintResult` at ``f_c`` (``I``,
        ``II``, ``III``, ``performance_error``, ``passivity_margin_deg`` ...)
        plus ``m_vs_over_m_st``.
    """
    params = table_parameters(config)
    ctrl = config["controller"]
    tm = table_model(params)
    vs = virtual_system(config, params.mass)
    vm = virtual_model(vs, config["vs"]["preset"])
    form = ctrl["form"]
    design = design_controller(
        tm, None if form == "tracking" else vm, form=form, fc_hz=float(ctrl["fc_hz"]), emit_warnings=False
    )
    save_design(design, out_path)
    result = design.constraints[0].to_dict()
    result.pop("fc_hz", None)
    result["m_vs_over_m_st"] = vs.m_vs / params.mass
    return result
