"""What the generated code can hold: the bound on its numbers and the check of each rendered number.

Part of the safety layer (:mod:`.safety`, which re-exports these names; the module docstring
there says why :data:`VALUE_LIMIT` prevents overflow).  Its own module so that what only checks
a number (:mod:`.io_units`, read with every lab file) does not import the command limits and,
through them, the ground-motion checks (issue 16, start-up).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ConfigError

#: Bound on every coefficient and internal state, by precision (see :mod:`.safety`).
VALUE_LIMIT = {"single": 1e18, "double": 1e150}


def _tiny(precision: str) -> float:
    return float(np.finfo(np.float32 if precision == "single" else np.float64).tiny)


def check_renderable(name: str, values: Any, precision: str, what: str = "values") -> None:
    """Refuse numbers the generated code cannot hold exactly in ``precision``.

    Every coefficient, VS parameter and limit the generators render must be
    finite in the precision, within :data:`VALUE_LIMIT` (so that the guards'
    overflow argument holds), and a non-zero value must not round to zero
    or to a subnormal number (it would lose its digits).

    Parameters
    ----------
    name : str
        What the values are (``"H_uz"``, ``"vs.m_vs"``), for the message.
    values : array_like
        The numbers (any shape), in double precision.
    precision : {"single", "double"}
    what : str
        What the values are, for the message (``"discrete coefficients"``).

    Raises
    ------
    ConfigError
        Naming ``name``, the first offending value and its position.
    """
    arr = np.asarray(values, dtype=float)
    limit, tiny = VALUE_LIMIT[precision], _tiny(precision)
    dtype = np.float32 if precision == "single" else np.float64
    with np.errstate(over="ignore", under="ignore"):
        rounded = np.abs(arr.astype(dtype).astype(float))
    bad = ~np.isfinite(arr) | ~(rounded <= limit) | ((arr != 0) & (rounded < tiny))
    if np.any(bad):
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        value = float(arr[index]) if arr.ndim else float(arr)
        where = f" at {list(index)}" if index else ""
        raise ConfigError(
            name,
            f"{what} finite, within +-{limit:g} and, unless zero, at least {tiny:.3g} in magnitude "
            f"({precision} precision; docs/implement.md, Safety layer){where}",
            value,
        )
