"""Passivity indices of any design: equivalent damping and the sampled-data margin (report Section 10.4).

Two numbers are added to a design's first constraint result:

* ``passivity_index`` [lbf*s/in]: ``min_f Re(1/H_vw(j 2 pi f))`` over the
  passivity band, the smallest equivalent viscous damping the controlled
  table presents to the article (``1/H_vw`` is force per velocity).  It is
  the input-feedforward-style "degree of passivity" the report asks for:
  negative where the table injects energy, and its size says by how much a
  damper would have to help.
* ``passivity_margin_sampled_deg`` [deg]: the passivity margin
  ``min_f (90 - |phase H_vw|)`` of the same controller on the exact
  sampled-data table (controller as its Tustin discretization, command held,
  see :mod:`.models`), which contains the half-sample hold that the
  first-order delay model lacks.

With them come the verdicts ``III_design_model`` (the first-order model with
its delay tolerance, as ``evaluate_constraints`` decides) and ``III_sampled``
(stable and the sampled margin plus the user's extra tolerance ``>= 0``; the
sampled model's delay and hold are exact, so no model tolerance), and ``III``
becomes the one of the chosen ``passivity_model`` (docs/design.md, "The
design model and the hold").
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...errors import ConfigError
from ...plant import TableParameters
from ..adapters import table_model
from ..constraints import PASSIVITY_MODELS, DesignCriteria, controlled_table
from ..controller import ControllerDesign
from ..forms import VirtualModel
from .exchange import log_points
from .models import SAMPLED_TOP_FRACTION, robust_set

#: Points per decade of the index grids.
INDEX_PER_DECADE = 1000


def sampled_margin_deg(
    design: ControllerDesign, params: TableParameters, vs: VirtualModel | None, band_hz: tuple[float, float]
) -> tuple[float, float]:
    """Passivity margin [deg] of ``design`` on the sampled-data table, and where [Hz]."""
    targets = {"vs": vs} if vs is not None else {}
    if not targets:
        return float("nan"), float("nan")
    (model,) = robust_set(params, targets, ("sampled",))
    f = log_points(band_hz, INDEX_PER_DECADE)
    r = model.responses(f)
    s = r.s_controller
    h = r.P_vw + r.P_vu * (design.H_uw(s) + design.H_uz(s) * r.Z)
    m = 90.0 - np.abs(np.degrees(np.angle(h)))
    i = int(np.argmin(m))
    return float(m[i]), float(f[i])


def passivity_index(
    design: ControllerDesign, params: TableParameters, vs: VirtualModel | None, band_hz: tuple[float, float]
) -> tuple[float, float]:
    """``min Re(1/H_vw)`` [lbf*s/in] on the first-order model over ``band_hz`` [Hz], and where [Hz]."""
    if vs is None:
        return float("nan"), float("nan")
    tm = table_model(params)
    ct = controlled_table(tm, vs, design.H_uz, design.H_uw, "standardized")
    f = log_points(band_hz, INDEX_PER_DECADE)
    damping = np.real(1.0 / ct.velocity_response(f))
    i = int(np.argmin(damping))
    return float(damping[i]), float(f[i])


def with_indices(
    design: ControllerDesign,
    params: TableParameters,
    vs: VirtualModel | None,
    criteria: DesignCriteria | None = None,
    warn: bool = True,
    passivity_model: str = "first-order",
) -> ControllerDesign:
    """``design`` with ``passivity_index``, ``passivity_margin_sampled_deg`` and ``III_sampled`` in its
    first constraint result, whose ``III`` is then the verdict of ``passivity_model``.

    Only the standardized form closes ``w -> z_vs`` through the VS model as
    modelled here; other forms (and tracking) are returned unchanged.

    Parameters
    ----------
    passivity_model : {"first-order", "sampled", "strictest"}
        Which verdict ``III`` reports: the first-order delay model with its
        tolerance (``III_design_model``, reproduces Table 9.5), the sampled-data
        table (``III_sampled``), or both.
    """
    if passivity_model not in PASSIVITY_MODELS:
        raise ConfigError("passivity_model", " | ".join(PASSIVITY_MODELS), passivity_model)
    if design.form != "standardized" or vs is None or not design.constraints:
        return design
    if not params.loop_time > 0:  # an analog table (loop_time 0): there is no sampled-data loop
        return dataclasses.replace(
            design,
            warnings=(
                *design.warnings,
                "analog table (loop_time 0): no sampled-data passivity margin or index",
            ),
        )
    c = criteria or DesignCriteria()
    nyq = 0.5 / params.loop_time
    margin, _ = sampled_margin_deg(design, params, vs, (c.passivity_low_hz, SAMPLED_TOP_FRACTION * nyq))
    index, _ = passivity_index(design, params, vs, (c.passivity_low_hz, nyq))
    c0 = design.constraints[0]
    # The sampled model has no delay-model error to credit (its hold and delay are exact): no tolerance
    # but the user's.  Stability is the design model's (the same poles up to the delay approximation).
    sampled = bool(c0.stable and margin + c.passivity_extra_tolerance_deg >= 0.0)
    design_model = c0.III if c0.III_design_model is None else c0.III_design_model
    verdict = {"first-order": design_model, "sampled": sampled, "strictest": design_model and sampled}
    first = dataclasses.replace(
        c0,
        passivity_margin_sampled_deg=margin,
        passivity_index=index,
        III_design_model=design_model,
        III_sampled=sampled,
        III=verdict[passivity_model],
    )
    notes = list(design.warnings)
    if warn and margin < 0 <= design.constraints[0].passivity_tolerant_margin_deg:
        notes.append(
            f"on the sampled-data table (with the command hold) the passivity margin is {margin:.2f} deg: "
            "less passive than the first-order delay model says (see docs/design.md)"
        )
    return dataclasses.replace(design, constraints=(first, *design.constraints[1:]), warnings=tuple(notes))
