"""The four forms of the impedance-matching MIL controller, before filtering.

Sign convention (used everywhere in :mod:`impedance_mil.design`, in the
design file and by :mod:`impedance_mil.implement`)::

    u = H_uz * r + H_uw * w [+ H_ufh * f_h]

with every term *added*.  ``r`` is the controller's reference input: the
target basemat acceleration ``z_vs`` [in/s**2] for the standardized form, the
ground acceleration ``a_g`` [in/s**2] for the tracking, general and
VS-specific forms.  ``w`` is the force of the test article on the table
[lbf] (``m_st*z = A_p*dP + w``), ``u`` the table's reference position
command [in].  The report writes the standardized controller with a minus
sign (Eq 6-7, 6-9: ``u = H_z^filter H_uz z_vs - H_w^filter H_uw w`` with
``H_uw = H_zw^st/H_zu^st``); here that minus sign is inside ``H_uw``.

================  ==========================================  ============
form              ideal controller (no filter)                report
================  ==========================================  ============
``general``       H_uz = H_zag^vs/H_zu^st,                    Eq 1-4, 6-3
                  H_uw = (H_zw^vs - H_zw^st)/H_zu^st
``vs-specific``   general + H_ufh = H_zfh^vs/H_zu^st          Eq 6-6
``standardized``  H_uz = 1/H_zu^st, H_uw = -H_zw^st/H_zu^st   Eq 6-7
``tracking``      standardized with r = z_vs = a_g            Eq 1-6, 8.1
================  ==========================================  ============
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ConfigError, UnstableDesignError, UnstableSystemError
from ..lazy import LazyModule
from ..lti import StateSpace
from ..systems import TransferFunction

#: python-control, imported on first use: only :meth:`TableModel.from_control` needs it (issue 16).
control = LazyModule("control")

#: The controller forms, in the order the report introduces them.
FORMS = ("standardized", "vs-specific", "tracking", "general")

#: Reference input of each form (the signal multiplied by ``H_uz``).
REFERENCE_INPUT = {"standardized": "z_vs", "tracking": "a_g", "general": "a_g", "vs-specific": "a_g"}

#: Top of the design's frequency axes when the loop is analog (loop time 0) [Hz].
ANALOG_NYQUIST_HZ = 1000.0

#: Real part below which a pole counts as on the imaginary axis [rad/s], relative to its size.
AXIS_RTOL = 1e-9


@dataclass(frozen=True)
class TableModel:
    """The linear shake-table model seen by the design (Eq 4-15a, 4-15d).

    Parameters
    ----------
    H_zu : TransferFunction
        Table acceleration per reference position command [in/s**2 per in].
    H_zw : TransferFunction
        Table acceleration per test-article force [in/s**2 per lbf].
    loop_time_s : float
        Controller loop time [s]; sets the Nyquist frequency and the
        tolerance of the first-order delay approximation (Section 4.3.4).
    parameters : mapping
        The table parameters (``TableParameters.to_dict()``), kept for the design file.
    capacity : mapping
        The stated capacity of a table given as a linear model (``[capacity]`` of
        its file: ``stroke`` [in], ``velocity`` [in/s], ``force`` [lbf], ``mass``
        [lbf*s**2/in], ``piston_area`` [in**2]; :mod:`impedance_mil.plant.capacity`),
        kept for the design file: the generated code's limits come from it.  Empty
        for a physical table, whose parameters imply it.
    """

    H_zu: TransferFunction
    H_zw: TransferFunction
    loop_time_s: float
    parameters: Mapping[str, Any] = field(default_factory=dict)
    capacity: Mapping[str, float] = field(default_factory=dict)

    @property
    def nyquist_hz(self) -> float:
        """Nyquist frequency of the controller loop [Hz] (:data:`ANALOG_NYQUIST_HZ` for an analog loop)."""
        return 0.5 / self.loop_time_s if self.loop_time_s > 0 else ANALOG_NYQUIST_HZ

    @classmethod
    def from_control(
        cls, sys, loop_time_s: float, *, output: str = "z", command: str = "u", force: str = "w"
    ) -> TableModel:
        """A table given as a python-control ``StateSpace`` or ``TransferFunction`` (continuous).

        ``sys`` has the inputs ``command`` (reference position [in]) and
        ``force`` (test-article force [lbf]) and the output ``output`` (table
        acceleration [in/s**2]), named as python-control names its signals
        (``control.ss(..., inputs=["u", "w"], outputs=["z"])``), in the
        internal units.  A state space is converted round-off safe
        (:meth:`TransferFunction.from_lti`); a transfer function's
        polynomials are taken as they are (python-control's own ss -> tf
        leaves round-off: ``8e-12 s**4`` in z/u of Table 4.1, so give the
        state space).

        Parameters
        ----------
        sys : control.StateSpace or control.TransferFunction
        loop_time_s : float
            Controller loop time [s] (0 for an analog loop).
        output, command, force : str
            Signal names in ``sys``.

        Raises
        ------
        ConfigError
            ``sys`` is discrete, or lacks a named signal (the message lists the names it has).

        Examples
        --------
        >>> import control
        >>> sys = control.ss([[-100.0]], [[100.0, 0.0]], [[-100.0]], [[100.0, 0.25]], inputs=["u", "w"], outputs=["z"])
        >>> table = TableModel.from_control(sys, 5e-4)
        >>> table.H_zu.relative_degree, table.H_zw.dcgain()
        (0, 0.25)
        """
        lti = StateSpace.from_control(sys)
        if lti.is_discrete:
            raise ConfigError("table", "a continuous python-control system (dt = 0)", lti.dt)
        H_zu, H_zw = (_control_path(sys, lti, output, name) for name in (command, force))
        return cls(H_zu, H_zw, float(loop_time_s))

    def to_control(self, *, output: str = "z", command: str = "u", force: str = "w"):
        """``H_zu`` and ``H_zw`` as one python-control ``TransferFunction`` (inputs ``command``, ``force``)."""
        return control.tf(
            [[self.H_zu.num, self.H_zw.num]],
            [[self.H_zu.den, self.H_zw.den]],
            inputs=[command, force],
            outputs=[output],
        )


def _control_path(sys, lti: StateSpace, output: str, input: str) -> TransferFunction:
    """One path of a python-control system: its own polynomials for a transfer function
    (a MIMO one is realized channel by channel, with every other channel's states), the
    round-off-safe conversion for a state space."""
    path = lti.channel(output, input)  # checks the names
    if isinstance(sys, control.TransferFunction):
        return TransferFunction.from_control(sys[lti.output_index(output), lti.input_index(input)])
    return TransferFunction.from_lti(path)


@dataclass(frozen=True)
class VirtualModel:
    """The linear part of a virtual system (Eq 5-2, 5-8, 5-13).

    Parameters
    ----------
    H_zag : TransferFunction
        Basemat acceleration per ground acceleration [dimensionless].
    H_zw : TransferFunction
        Basemat acceleration per test-article force (the VS impedance) [in/s**2 per lbf].
    H_zfh : TransferFunction or None
        Basemat acceleration per nonlinear input ``f_h`` (LR, FP); None for a linear VS.
    kind : str
        ``"SD"``, ``"LR"``, ``"FP"``, ``"rigid"`` (tracking) or a user label.
    name : str or None
        Preset name (e.g. ``"SD2"``).
    parameters : mapping
        The VS parameters (``vs.to_dict()``), kept for the design file.
    equivalent : EquivalentLinearization or None
        Equivalent linearization of a hysteretic VS at a design amplitude
        (:mod:`impedance_mil.design.linearize`); when present it replaces
        ``H_zw`` in the constraints of the standardized form.  None: the
        linear part with ``f_h`` open is used.
    definition : mapping or None
        The VS type's definition (``VSDefinition.to_dict()``) when it is not a
        built-in type, so that the design file alone rebuilds the exact VS.
    """

    H_zag: TransferFunction
    H_zw: TransferFunction
    H_zfh: TransferFunction | None = None
    kind: str = "linear"
    name: str | None = None
    parameters: Mapping[str, Any] = field(default_factory=dict)
    equivalent: Any = None
    definition: Mapping[str, Any] | None = None

    @classmethod
    def rigid(cls) -> VirtualModel:
        """The zero-impedance environment of acceleration tracking: ``H_zag = 1``, ``H_zw = 0`` (Section 8.1)."""
        return cls(TransferFunction.constant(1.0), TransferFunction.constant(0.0), None, kind="rigid")


@dataclass(frozen=True)
class IdealController:
    """An unfiltered (generally improper) MIL controller ``u = H_uz r + H_uw w + H_ufh f_h``.

    Attributes
    ----------
    form : str
        One of :data:`FORMS`.
    reference : str
        ``"z_vs"`` or ``"a_g"``: the signal that ``H_uz`` multiplies.
    H_uz, H_uw : TransferFunction
        [in per in/s**2], [in per lbf].
    H_ufh : TransferFunction or None
        [in per unit of f_h]; only for the VS-specific form of LR/FP.
    """

    form: str
    reference: str
    H_uz: TransferFunction
    H_uw: TransferFunction
    H_ufh: TransferFunction | None = None

    def paths(self) -> dict[str, TransferFunction]:
        """The controller paths by name (``"z"``, ``"w"``, ``"fh"``)."""
        out = {"z": self.H_uz, "w": self.H_uw}
        if self.H_ufh is not None:
            out["fh"] = self.H_ufh
        return out


def right_half_plane(roots, rtol: float = AXIS_RTOL) -> np.ndarray:
    """The roots [rad/s] in the open right half plane: ``Re r > rtol*max(|r|, 1)``."""
    r = np.asarray(roots)
    return r[r.real > rtol * np.maximum(np.abs(r), 1.0)]


def imaginary_axis(roots, rtol: float = AXIS_RTOL) -> np.ndarray:
    """The roots [rad/s] on the imaginary axis (the origin included): ``|Re r| <= rtol*max(|r|, 1)``."""
    r = np.asarray(roots)
    return r[np.abs(r.real) <= rtol * np.maximum(np.abs(r), 1.0)]


def environment(form: str, vs: VirtualModel | None) -> VirtualModel:
    """The VS model a design of ``form`` answers to: the rigid environment for tracking or without a VS."""
    return VirtualModel.rigid() if form == "tracking" or vs is None else vs


def check_table(table: TableModel) -> None:
    """Refuse a table model that no impedance-matching controller can invert.

    Every form (tracking included) needs the force path ``H_zw``: without it
    the standardized controller's ``H_uw`` is zero, and constraint I and the
    passivity check III, relative to the bare table's impedance, have nothing
    to measure (NaN errors and a vacuous pass).

    Raises
    ------
    ConfigError
        ``H_zw`` is zero (naming ``H_zw``, the missing path).
    UnstableSystemError
        ``H_zu`` or ``H_zw`` has poles in the closed right half plane (the
        table loop itself is unstable).
    UnstableDesignError
        ``H_zu`` is zero, or has zeros in the right half plane (its inverse,
        the controller, would be unstable), or is improper.
    """
    if table.H_zu.is_zero:
        raise UnstableDesignError("H_zu of the table is zero: the table does not respond to u")
    if table.H_zw.is_zero:
        raise ConfigError(
            "H_zw",
            "a table model with a test-article force path (H_zw, z per w, not zero): every MIL form "
            "matches or removes the table's own impedance H_zw, and its constraints are relative to it",
            "0",
        )
    for name, H in (("H_zu", table.H_zu), ("H_zw", table.H_zw)):
        if not H.is_stable():
            worst = max(H.poles(), key=lambda p: p.real)
            raise UnstableSystemError(
                f"table {name} has a pole at {worst.real:.4g}{worst.imag:+.4g}j rad/s (unstable table loop); "
                "reduce Ke or Kp, or shorten loop_time"
            )
        if not H.is_proper:
            raise UnstableDesignError(f"table {name} is improper (relative degree {H.relative_degree})")
    bad = right_half_plane(table.H_zu.zeros())
    if bad.size:
        raise UnstableDesignError(
            f"H_zu has a right-half-plane zero at {bad[0].real:.4g}{bad[0].imag:+.4g}j rad/s: "
            "its inverse (the MIL controller) would be unstable"
        )


def check_virtual(vs: VirtualModel) -> None:
    """Refuse a VS whose linear part is improper or unstable.

    Poles on the imaginary axis (the lossless linear part of an FP system,
    Eq 5-13) are accepted.

    Raises
    ------
    UnstableDesignError
        A VS transfer function is improper or has a pole with positive real part.
    """
    for name, H in (("H_zag", vs.H_zag), ("H_zw", vs.H_zw), ("H_zfh", vs.H_zfh)):
        if H is None:
            continue
        if not H.is_proper:
            raise UnstableDesignError(
                f"virtual system {name} is improper (relative degree {H.relative_degree}): not causal"
            )
        bad = right_half_plane(H.poles())
        if bad.size:
            raise UnstableDesignError(
                f"virtual system {name} has an unstable pole at {bad[0].real:.4g}{bad[0].imag:+.4g}j rad/s"
            )


def ideal_controller(form: str, table: TableModel, vs: VirtualModel | None = None) -> IdealController:
    """The unfiltered controller of one form (Eq 1-4, 1-6, 6-3, 6-6, 6-7).

    Parameters
    ----------
    form : str
        One of :data:`FORMS`.
    table : TableModel
        The linear table model.
    vs : VirtualModel, optional
        Required for ``general`` and ``vs-specific``; ignored by
        ``standardized`` (which depends on the table only) and ``tracking``.

    Returns
    -------
    IdealController
        Improper in general (``H_uz = 1/H_zu`` has relative degree -3).

    Raises
    ------
    ConfigError
        Unknown form, a VS missing where the form needs it, or the
        vs-specific form for a linear VS (it has no f_h).
    UnstableDesignError, UnstableSystemError
        See :func:`check_table`, :func:`check_virtual`.
    """
    if form not in FORMS:
        raise ConfigError("form", "one of " + ", ".join(FORMS), form)
    check_table(table)
    H_zu, H_zw = table.H_zu, table.H_zw
    if form in ("standardized", "tracking"):
        H_uz = H_zu.inv().minreal()
        H_uw = -(H_zw.div_cancel(H_zu))
        return IdealController(form, REFERENCE_INPUT[form], H_uz, H_uw)
    if vs is None:
        raise ConfigError("vs", f"the virtual system's transfer functions for the {form} form")
    check_virtual(vs)
    H_uz = vs.H_zag.div_cancel(H_zu)
    H_uw = (vs.H_zw - H_zw).minreal().div_cancel(H_zu)
    H_ufh = None
    if form == "vs-specific":
        if vs.H_zfh is None:
            raise ConfigError(
                "form",
                f"a form other than vs-specific for the linear {vs.kind} system, which has no "
                "nonlinear force f_h (H_zfh); use general or standardized",
                form,
            )
        H_ufh = vs.H_zfh.div_cancel(H_zu)
    return IdealController(form, REFERENCE_INPUT[form], H_uz, H_uw, H_ufh)
