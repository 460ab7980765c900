"""A design file run as it was designed: ``imil simulate --design`` and ``imil track --design``.

A lab designs once (``imil design ... -o design.json``, by filter or by
optimization), exports the controller, and wants the virtual lab to run the
very controller it exported.  The run takes from the design file its
controller paths, its cut-off (the Tustin pre-warp of
:func:`~impedance_mil.implement.discretize`, as ``imil export`` uses it) and,
for MIL, its virtual system, rebuilt parameter by parameter
(:func:`~impedance_mil.implement.export.designed_vs`).

What is refused, in one line naming ``--design``:

* a form the run cannot execute: a MIL run executes the standardized form, a
  tracking run the tracking form (the VS-specific form's ``f_h`` path has no
  runtime);
* a loop time other than the run's: the controller was discretized for it;
* a design made for another table, unless ``--force`` (a lab may mean to test
  how a controller copes with a table that drifted): the differing
  parameters are named, and with ``--force`` they become warnings.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ..design import ControllerDesign, load_design
from ..errors import ConfigError
from ..implement.export import LOOP_TIME_RTOL
from ..plant import TableParameters
from ..plant.lti_table import LTITable
from ..plant.parameters import FIELDS

#: The form of the design each kind of run executes.
RUN_FORMS = {"mil": "standardized", "track": "tracking"}

#: Relative tolerance of a table parameter of the design against the run's (file round trip).
TABLE_RTOL = 1e-9

#: Relative tolerance of an LTI table's path responses, the design's against the run's.
LTI_RTOL = 1e-6


def read_design(path: str | Path, kind: str, key: str = "--design") -> ControllerDesign:
    """The design file ``path`` for a run of ``kind`` (``"mil"`` or ``"track"``).

    Raises
    ------
    DataFileError
        The file is missing or is not a design file (:func:`~impedance_mil.design.load_design`).
    ConfigError
        The design's form is not the one this kind of run executes.
    """
    design = load_design(path)
    form = RUN_FORMS[kind]
    if design.form != form:
        raise ConfigError(
            key,
            f"a design of the {form} form (a {'MIL' if kind == 'mil' else 'tracking'} run executes it)",
            f"{design.form} form in {path}",
        )
    return design


def check_loop_time(
    design: ControllerDesign, table: TableParameters | LTITable, key: str = "--design"
) -> None:
    """Refuse a design discretized for another loop time than the run's table [s]."""
    if not math.isclose(design.loop_time_s, table.loop_time, rel_tol=LOOP_TIME_RTOL):
        raise ConfigError(
            key,
            f"a design for the run's loop time {table.loop_time:g} s (its controller is discretized for it)",
            f"{design.loop_time_s:g} s",
        )


def table_differences(design: ControllerDesign, table: TableParameters | LTITable) -> list[str]:
    """One sentence per parameter in which the design's table differs from the run's (internal units).

    A design file records the physical parameters of its table; for an LTI
    table, the paths ``H_zu`` and ``H_zw`` it was designed on (compared as
    frequency responses, :func:`lti_differences`).
    """
    if not design.table:
        if design.table_paths and isinstance(table, LTITable):
            return lti_differences(design, table)
        return ["the design file records no table parameters, so it cannot be compared with the run's table"]
    if isinstance(table, LTITable):
        return [
            "the design was made for a physical table and the run's table is an LTI model: not comparable"
        ]
    run = table.to_dict()
    out = []
    for name, value in run.items():
        designed = design.table.get(name)
        if designed is None or _same(designed, value):
            continue
        unit = FIELDS[name].unit
        out.append(f"{name} = {_text(designed)} in the design, {_text(value)} in the run [{unit}]")
    return out


#: Decades of the frequency grid on which an LTI design's paths are compared with the run's [Hz].
_LTI_GRID_HZ = (1e-2, 1e3)


def lti_differences(design: ControllerDesign, table: LTITable) -> list[str]:
    """One sentence per path (``H_zu``, ``H_zw``) whose response differs from the run's LTI table.

    The design's and the run's paths are compared on 0.01 Hz to 1 kHz (or the
    loop's Nyquist frequency, if lower), 50 points per decade: a path differs
    when its largest relative difference exceeds :data:`LTI_RTOL`
    (a file round trip of polynomial coefficients, realized again, is within
    1e-12 here; another table is not).
    """
    top = _LTI_GRID_HZ[1] if table.loop_time <= 0 else min(_LTI_GRID_HZ[1], 0.5 / table.loop_time)
    f = np.geomspace(_LTI_GRID_HZ[0], top, int(50 * np.log10(top / _LTI_GRID_HZ[0])) + 1)
    out = []
    for name, (output, command) in (("H_zu", ("z", "u")), ("H_zw", ("z", "w"))):
        designed = design.table_paths[name].frequency_response(f)
        run = table.tf(output, command).frequency_response(f)
        scale = np.maximum(np.abs(run), np.finfo(float).tiny)
        worst = float(np.max(np.abs(designed - run) / scale))
        if not worst <= LTI_RTOL:
            out.append(
                f"{name} differs from the run's table by up to {worst:.3g} (relative) over {f[0]:g}-{top:g} Hz"
            )
    return out


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, (list, tuple)) or isinstance(b, (list, tuple)):
        a, b = list(a), list(b)
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    try:
        return math.isclose(float(a), float(b), rel_tol=TABLE_RTOL, abs_tol=0.0)
    except (TypeError, ValueError):
        return a == b


def _text(value: Any) -> str:
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_text(v) for v in value) + "]"
    return f"{float(value):g}" if isinstance(value, (int, float)) else str(value)
