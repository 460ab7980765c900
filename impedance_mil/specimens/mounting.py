"""Mounting dynamics: a flexible platen mode and the load cells between the table and the article.

The lab's table is a rigid body (the actuator and the accelerometer sit on
it; its acceleration is ``z`` [in/s**2]).  Two optional parts sit between it
and the test article:

* **a flexible platen mode**: modal mass ``m_p`` [lbf*s**2/in], frequency
  ``f_p`` [Hz], damping ratio ``zeta_p``.  The table's total mass stays
  ``m_st``: the rigid body keeps ``m_st - m_p`` and the mode is a
  base-excited oscillator on it, ``q_p'' = -z - 2 zeta_p w_p q_p' - w_p**2 q_p``,
  whose force on the rigid body is ``m_p (w_p**2 q_p + 2 zeta_p w_p q_p')``
  (``-m_p z`` at low frequency: nothing changes there);
* **load cells** (with their frame) between the table and the article: total
  axial stiffness ``k`` [lbf/in], damping ``c`` [lbf*s/in] and an optional
  base-plate mass ``m_b`` [lbf*s**2/in] above the cells, on which the article
  stands.  With ``d`` the cells' deflection (base plate relative to the
  table) the base plate accelerates by ``a_b = (-k d - c d' + w_a) / m_b``
  with ``w_a = C_a x_a + D_a a_b`` the article's force on it, i.e.
  ``a_b = (-k d - c d' + C_a x_a) / (m_b - D_a)``; the cells push the table
  with ``w_LC = k d + c d'``.

:func:`mount` composes an article's state space (input: its base
acceleration, output: the force on its base) with these parts into a
:class:`MountedSpecimen`, again input ``z`` and output ``w``, with a second
output: the force through the load cells, ``w_LC = C_lc x + D_lc z``, what the
load-cell sensors read.

**The table's mass.**  The rigid body's equation is
``(m_st - m_p) z = A_p dP + w_table - F``, with ``w_table`` the force of
the platen mode and the load cells on it.  Adding ``m_p z`` to both sides
gives ``m_st z = A_p dP + (w_table + m_p z) - F``: the same physics with the
table's mass ``m_st`` and the specimen output ``w = w_table + m_p z``.  The
lab and the linear design check use that form (the composed state space's
``D`` carries ``+m_p``), because both derive the oil column's stiffness from
``m_st`` and the oil-column frequency (Eq 4-10a): replacing the mass would
change the oil column.  :attr:`MountedSpecimen.rigid_table_mass` and
:meth:`MountedSpecimen.table_force_state_space` give the other form (tests
check that both linearize alike).  ``w`` is thus the force on the table as
its nominal rigid-body model sees it, ``w = w_LC - m_p q_p''``: exactly what
``w_FE = m_st z - A_p dP`` estimates, and no longer the load-cell force
above the platen mode.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule
from ..units import G0, TWO_PI
from .arrays import specimen_state_space

if TYPE_CHECKING:
    from ..systems import TransferFunction
    from .statespace import SpecimenStateSpace

# The lab file reads the parameters below in configuration commands, which import no numba;
# the state space (numba's rk4_step lives beside it) is imported when a specimen is composed.
statespace = LazyModule("impedance_mil.specimens.statespace")


@dataclass(frozen=True)
class PlatenMode:
    """A flexible mode of the platen, as a base-excited oscillator on the table's rigid body.

    Parameters
    ----------
    modal_mass : float
        Modal mass m_p [lbf*s**2/in], > 0 and below the table's m_st.
    frequency_hz : float
        Natural frequency f_p with the table held still [Hz], > 0.
    damping_ratio : float
        Damping ratio zeta_p [-], >= 0.
    """

    modal_mass: float
    frequency_hz: float
    damping_ratio: float

    def __post_init__(self):
        for key, value in (("modal_mass", self.modal_mass), ("frequency", self.frequency_hz)):
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"dynamics.platen.{key}", "a positive value", value)
        if not (math.isfinite(self.damping_ratio) and self.damping_ratio >= 0):
            raise ConfigError("dynamics.platen.damping", "a damping ratio >= 0", self.damping_ratio)

    @property
    def omega(self) -> float:
        """Natural frequency [rad/s]."""
        return TWO_PI * self.frequency_hz

    def to_dict(self) -> dict:
        return {
            "modal_mass": self.modal_mass,
            "frequency": self.frequency_hz,
            "damping": self.damping_ratio,
        }


@dataclass(frozen=True)
class LoadCells:
    """The load cells and their frame between the table and the article.

    Parameters
    ----------
    stiffness : float
        Total axial stiffness k of the cells and their frame [lbf/in], > 0.
    damping : float
        Viscous damping: a coefficient c [lbf*s/in] when ``damping_is_ratio``
        is false, else a ratio zeta [-] of the article and base plate on the
        cells, ``c = 2 zeta sqrt(k (m_b + M))`` with M the article's total mass.
    base_mass : float
        Mass of the base plate above the cells m_b [lbf*s**2/in], >= 0.
    damping_is_ratio : bool
        How ``damping`` is given.
    """

    stiffness: float
    damping: float = 0.0
    base_mass: float = 0.0
    damping_is_ratio: bool = True

    def __post_init__(self):
        if not (math.isfinite(self.stiffness) and self.stiffness > 0):
            raise ConfigError("dynamics.load_cells.stiffness", "a positive stiffness", self.stiffness)
        if not (math.isfinite(self.damping) and self.damping >= 0):
            raise ConfigError("dynamics.load_cells.damping", "a damping >= 0", self.damping)
        if not (math.isfinite(self.base_mass) and self.base_mass >= 0):
            raise ConfigError("dynamics.load_cells.base_mass", "a mass >= 0", self.base_mass)

    def coefficient(self, carried_mass: float) -> float:
        """Damping coefficient c [lbf*s/in] with ``carried_mass`` [lbf*s**2/in] on the cells."""
        if not self.damping_is_ratio:
            return self.damping
        return 2.0 * self.damping * math.sqrt(self.stiffness * carried_mass)

    def to_dict(self) -> dict:
        return {
            "stiffness": self.stiffness,
            "damping_ratio": self.damping if self.damping_is_ratio else None,
            "damping_coefficient": None if self.damping_is_ratio else self.damping,
            "base_mass": self.base_mass,
        }


@dataclass(frozen=True)
class Mounting:
    """What sits between the table's rigid body and the article (either part may be absent)."""

    platen: PlatenMode | None = None
    load_cells: LoadCells | None = None

    def __bool__(self) -> bool:
        return self.platen is not None or self.load_cells is not None

    def check_table_mass(self, table_mass: float, key: str = "dynamics.platen.modal_mass") -> None:
        """Refuse a platen modal mass at or above the table's ``table_mass`` m_st [lbf*s**2/in]."""
        if self.platen is not None and self.platen.modal_mass >= table_mass:
            raise ConfigError(
                key,
                f"a modal mass below the table's moving mass m_st = {table_mass:.6g} lbf*s^2/in",
                self.platen.modal_mass,
            )

    def to_dict(self) -> dict:
        return {
            "platen": None if self.platen is None else self.platen.to_dict(),
            "load_cells": None if self.load_cells is None else self.load_cells.to_dict(),
        }


@dataclass(frozen=True)
class LoadCellOutput:
    """The second output of a mounted specimen: ``w_LC = C x + D z`` [lbf], the force through the load cells."""

    C: np.ndarray
    D: float


def _article_mass(article) -> float:
    """The article's total mass [lbf*s**2/in] (minus its DC impedance when it has no ``total_mass``)."""
    if article is None:
        return 0.0
    if hasattr(article, "total_mass"):
        return float(article.total_mass)
    A, B, C, D = specimen_state_space(article)
    return -(D - float(C @ np.linalg.solve(A, B))) if B.size else -D


class MountedSpecimen:
    """An article on its mounting: input the table's acceleration z, outputs w and w_LC.

    The specimen contract of :class:`~impedance_mil.specimens.structural.Specimen`
    (``state_space``, ``impedance``, ``driving_point_impedance``, ``total_mass``,
    ``total_weight``, ``to_dict``).  Built by :func:`mount`.  :meth:`state_space` is the form for a table of
    mass m_st (module docstring); :attr:`load_cell` the load cells' output.

    Parameters
    ----------
    article : Specimen or None
        The test article (None: nothing above the cells but the base plate).
    mounting : Mounting
    table_mass : float
        The table's total moving mass m_st [lbf*s**2/in].
    """

    def __init__(self, article, mounting: Mounting, table_mass: float):
        mounting.check_table_mass(table_mass)
        self.article = article
        self.mounting = mounting
        self.table_mass = float(table_mass)
        self._build()

    # -- composition ------------------------------------------------------------------
    def _build(self) -> None:
        Aa, Ba, Ca, Da = specimen_state_space(self.article)
        n = Ba.size
        cells = self.mounting.load_cells
        carried = (cells.base_mass if cells else 0.0) + _article_mass(self.article)
        if cells is not None and carried > 0:
            base = cells.base_mass - Da  # the mass the cells accelerate directly (plate + rigid part)
            if base <= 0:
                raise ConfigError(
                    "dynamics.load_cells.base_mass",
                    "a base-plate mass > 0 for an article with no rigidly attached mass",
                    cells.base_mass,
                )
            k, c = cells.stiffness, cells.coefficient(carried)
            # states [d, d', x_a]; a_b = (-k d - c d' + Ca x_a) / base
            ab = np.concatenate([[-k, -c], Ca]) / base
            m = 2 + n
            A = np.zeros((m, m))
            A[0, 1] = 1.0
            A[1] = ab
            A[2:, 2:] = Aa
            A[2:] += np.outer(Ba, ab)
            B = np.zeros(m)
            B[1] = -1.0
            C_lc = np.zeros(m)
            C_lc[:2] = k, c
            D_lc = 0.0
        else:  # no cells, or nothing on them: the article stands on the table
            A, B, C_lc, D_lc = Aa, Ba, Ca, Da
        A, B, C, C_lc, D = self._with_platen(A, B, C_lc, D_lc, cells is None or carried <= 0)
        self._table_form = statespace.SpecimenStateSpace(A, B, C, D)
        self._load_cell = LoadCellOutput(np.ascontiguousarray(C_lc), float(D_lc))
        self._carried = carried

    def _with_platen(self, A, B, C_lc, D_lc, interleave: bool):
        """Add the platen mode; returns ``(A, B, C, C_lc, D)`` of the table form, D with ``+m_p``.

        Without load cells the mode's states go first in each half of the
        article's (``[q_p, q_a, q_p', q_a']``): a bank of oscillators stays one.
        """
        p = self.mounting.platen
        if p is None:
            return A, B, C_lc.copy(), C_lc, D_lc
        m = B.size
        w2, cw = p.omega**2, 2.0 * p.damping_ratio * p.omega
        half = m // 2 if interleave and m % 2 == 0 else 0
        order = [m] + list(range(half)) + [m + 1] + list(range(half, m))  # old index per new slot
        big = np.zeros((m + 2, m + 2))
        big[:m, :m] = A
        big[m, m + 1] = 1.0
        big[m + 1, m] = -w2
        big[m + 1, m + 1] = -cw
        bb = np.concatenate([B, [0.0, -1.0]])
        c_lc = np.concatenate([C_lc, [0.0, 0.0]])
        c = np.concatenate([C_lc, [p.modal_mass * w2, p.modal_mass * cw]])
        P = np.array(order)
        return big[np.ix_(P, P)], bb[P], c[P], c_lc[P], D_lc + p.modal_mass

    # -- the Specimen contract -----------------------------------------------------------
    def state_space(self) -> SpecimenStateSpace:
        """Input z [in/s**2], output ``w = w_table + m_p z`` [lbf] (for a table of mass m_st)."""
        return self._table_form

    @property
    def load_cell(self) -> LoadCellOutput:
        """The load cells' force on the table ``w_LC = C x + D z`` [lbf] on the same states."""
        return self._load_cell

    @property
    def rigid_table_mass(self) -> float:
        """The table's rigid-body mass without the platen's modal mass, m_st - m_p [lbf*s**2/in]."""
        p = self.mounting.platen
        return self.table_mass - (p.modal_mass if p else 0.0)

    def table_force_state_space(self) -> SpecimenStateSpace:
        """The same states with output ``w_table`` [lbf], the force on the rigid body of mass :attr:`rigid_table_mass`."""
        p = self.mounting.platen
        ss = self._table_form
        return statespace.SpecimenStateSpace(ss.A, ss.B, ss.C, ss.D - (p.modal_mass if p else 0.0))

    def impedance(self) -> TransferFunction:
        """Transfer function ``w/z`` [lbf per in/s**2] (s in rad/s); tends to ``-total_mass`` as ``s -> 0``."""
        return self.state_space().transfer_function()

    def driving_point_impedance(self, f_hz) -> np.ndarray:
        """Force on the mounted specimen per table velocity, ``-w / v`` [lbf*s/in], at ``f_hz`` [Hz]."""
        f = np.atleast_1d(np.asarray(f_hz, dtype=float))
        return -self.state_space().frequency_response(f) * (1j * TWO_PI * f)

    @property
    def total_mass(self) -> float:
        """Mass carried by the table beyond m_st [lbf*s**2/in]: the article and the base plate."""
        return self._carried

    @property
    def total_weight(self) -> float:
        return self.total_mass * G0

    def to_dict(self) -> dict[str, Any]:
        art = self.article
        return {
            "kind": "mounted",
            "article": None if art is None else (art.to_dict() if hasattr(art, "to_dict") else repr(art)),
            "mounting": self.mounting.to_dict(),
            "table_mass": self.table_mass,
        }


def mount(article, mounting: Mounting | None, table_mass: float):
    """The article on its mounting, or the article itself when there is none.

    Parameters
    ----------
    article : Specimen or None
        The test article (input: its base acceleration [in/s**2], output: the
        force on its base [lbf]).
    mounting : Mounting or None
        None, or a mounting without parts: ``article`` unchanged (the lab is
        then bit-identical to one without mounting).
    table_mass : float
        The table's moving mass m_st [lbf*s**2/in].

    Returns
    -------
    Specimen or MountedSpecimen or None
    """
    if not mounting:
        return article
    return MountedSpecimen(article, mounting, table_mass)


def load_cell_output(specimen) -> LoadCellOutput | None:
    """The load-cell output of a mounted specimen (None: the load cells read the specimen's w)."""
    return getattr(specimen, "load_cell", None) if isinstance(specimen, MountedSpecimen) else None


__all__ = [
    "LoadCellOutput",
    "LoadCells",
    "MountedSpecimen",
    "Mounting",
    "PlatenMode",
    "load_cell_output",
    "mount",
]
