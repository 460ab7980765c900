"""A straightforward reference implementation of the virtual table: solve_ivp between ticks.

:class:`ScipyTable` is :class:`~impedance_mil.lab.plant_interface.VirtualTable`
with the fixed-step RK4 of the compiled loop replaced by
``scipy.integrate.solve_ivp`` (adaptive RK45, tight tolerances) over each
loop time; sensing, the hydraulic loop and the interlocks are the same.  Run
it with :func:`impedance_mil.lab.loop.simulate_interface` (controller stepped
in Python).  It serves two purposes: an independent check of the RK4
integration (tests) and the baseline of ``benchmarks/bench_lab.py``.
"""

from __future__ import annotations

import numpy as np
import scipy.integrate

from .plant_interface import VirtualTable
from .stepping import coupled_derivative


class ScipyTable(VirtualTable):
    """The virtual table integrated with ``solve_ivp`` between loop ticks.

    Parameters are those of :class:`VirtualTable`, plus ``rtol`` and ``atol``
    (relative and absolute tolerances of RK45; ``atol`` applies to every state
    in its own unit).
    """

    def __init__(
        self,
        table,
        specimen=None,
        sensors=None,
        limits=None,
        seed: int = 0,
        feedback: str = "lc",
        quantize: bool = True,
        rtol: float = 1e-8,
        atol: float = 1e-9,
    ):
        self.rtol = rtol
        self.atol = atol
        super().__init__(
            table,
            specimen=specimen,
            sensors=sensors,
            limits=limits,
            substeps=1,
            seed=seed,
            feedback=feedback,
            quantize=quantize,
        )

    def _rhs(self, t, y):
        out = np.empty_like(y)
        coupled_derivative(self.plant.table, y, *self.plant.specimen, self.current, out)
        return out

    def advance(self) -> None:
        t0 = self.time_s
        sol = scipy.integrate.solve_ivp(
            self._rhs, (t0, t0 + self.loop_time), self.y, method="RK45", rtol=self.rtol, atol=self.atol
        )
        self.y[:] = sol.y[:, -1]
        self._step()
