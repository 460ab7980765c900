"""A specimen's state space as plain arrays, without numba (one definition for the lab and the mounting).

:func:`specimen_state_space` is what the lab's substep rule and plant interface couple with
the table (:mod:`impedance_mil.lab.substeps`, which re-exports it) and what
:mod:`impedance_mil.specimens.mounting` composes with the load cells and the platen.
"""

from __future__ import annotations

import numpy as np


def specimen_state_space(specimen) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """``(A, B, C, D)`` of a specimen (input z [in/s^2], output w [lbf]); ``None``: no states.

    ``specimen`` has a ``state_space()`` method or is a state space itself (``A``, ``B``,
    ``C``, ``D``); B and C come back as vectors, D as a float.
    """
    if specimen is None:
        return np.zeros((0, 0)), np.zeros(0), np.zeros(0), 0.0
    ss = specimen.state_space() if hasattr(specimen, "state_space") else specimen
    n = np.size(ss.B)
    return (
        np.asarray(ss.A, dtype=float).reshape(n, n),
        np.asarray(ss.B, dtype=float).ravel(),
        np.asarray(ss.C, dtype=float).ravel(),
        float(ss.D),
    )
