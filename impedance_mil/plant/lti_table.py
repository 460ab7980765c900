"""A shake table known only as a linear model: transfer functions, zeros/poles/gain or a state space.

A lab may have its table as an identified or published linear model rather
than as the report's physical parameters (Table 4.1).  A table file with a
``[model]`` section gives it (issue 13)::

    [model]
    kind = "transfer-function"          # or "zpk", "state-space"
    loop_time = "500 us"                # required: the controller loop time
    delay = "included"                  # or "first-order", "pade", "sampled"
    units = { z = "in/s**2", u = "in", w = "lbf" }   # any pint units of these dimensions
    H_zu = { num = [...], den = [...] } # descending powers of s [rad/s], the file's units
    H_zw = { num = [...], den = [...] }

* ``kind = "transfer-function"``: ``H_<output><input> = { num, den }`` for the
  outputs ``z`` (acceleration), ``x`` (displacement), ``v`` (velocity), ``dp``
  (differential pressure) and the inputs ``u`` (reference position command)
  and ``w`` (test-article force).  ``H_zu`` is required; without any ``H_?w``
  the table has no force path (the MIL forms refuse it, naming ``H_zw``).
  When ``x`` (``v``) is not given and every given ``z`` path has two (one)
  exact zeros at the origin (trailing zero coefficients), ``x = z/s**2``
  (``v = z/s``) is derived, exactly.
* ``kind = "zpk"``: ``H_zu = { zeros = [...], poles = [...], gain = k }`` with
  ``H = k prod(s - z_i)/prod(s - p_i)``, roots in rad/s; a real root is a
  number, a complex root a pair ``[re, im]``, and every complex root is given
  together with its conjugate (``[re, im]`` and ``[re, -im]``; an unpaired
  one is refused).
* ``kind = "state-space"``: ``A``, ``B``, ``C``, ``D`` (``D`` optional: zero
  feedthrough), ``inputs`` (``["u", "w"]`` or ``["u"]``) and ``outputs``
  (``"z"`` and any of ``"x"``, ``"v"``, ``"dp"``), ``A`` in 1/s.

``units`` names the unit of every signal the model uses; they are converted
by dimension to the internal units (in, lbf, in/s**2, in/s, psi;
:mod:`impedance_mil.units`).  ``allow_unstable = true`` accepts a model with
poles in the closed right half plane (refused otherwise).

Delay treatment (``delay``), of the controller's one-loop delay on the command
``u -> e^{-s tau}``, tau = ``loop_time``:

* ``"included"``: the model already holds it (e.g. identified from the loop);
  nothing is added;
* ``"first-order"``: the design model adds the first-order lag
  ``1/(1 + s tau)`` on the command (proper, one state; the ``1 - s tau`` of the
  physical model's feedback would differentiate the command);
* ``"pade"``: a Pade approximation of order ``pade_order`` (default 6) on the command;
* ``"sampled"``: the design uses the first-order lag (the continuous
  constraints need a continuous model); the exact treatment, a command held
  over one loop and applied one loop late, is the sampled-data loop's
  (:meth:`LTITable.sampled_command`, ZOH of the model with one loop of delay).

:meth:`LTITable.state_space` is the file's model (internal units, no delay
added); :meth:`LTITable.design_state_space`, :meth:`~LTITable.tf`,
:meth:`~LTITable.poles` are of the model with the delay treatment.  A
transfer-function model is realized input by input (controllable canonical
form with the common denominator of the input's paths), so a pole shared by
``H_zu`` and ``H_zw`` is a state of each input's part; :meth:`LTITable.poles`
lists it once.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..lti import StateSpace
from ..systems import CANCEL_RTOL, TransferFunction, pole_table
from .capacity import TableCapacity
from .linear import DEFAULT_PADE_ORDER, MAX_PADE_ORDER, command_delayed, first_order_lag, pade_state_space
from .statespace import TableStateSpace

#: Model kinds of ``[model] kind``.
KINDS = ("transfer-function", "zpk", "state-space")
#: Delay treatments of ``[model] delay`` (module docstring).
LTI_DELAYS = ("included", "first-order", "pade", "sampled")
#: Inputs of an LTI table, in order: the command u [in], the test-article force w [lbf].
LTI_INPUTS = ("u", "w")
#: Outputs an LTI table may have (``z`` always, first).
LTI_OUTPUTS = ("z", "x", "v", "dp")
#: Internal unit of each signal (pint expressions).
SIGNAL_UNITS = {
    "u": "inch",
    "w": "force_pound",
    "z": "inch / second ** 2",
    "x": "inch",
    "v": "inch / second",
    "dp": "psi",
}
#: Zeros at the origin of z/input that make each derived output: x = z/s**2, v = z/s.
DERIVED_OUTPUTS = {"x": 2, "v": 1}
#: Relative tolerance under which two poles of different inputs' parts are one pole.
SHARED_POLE_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class LTITable:
    """A shake table given as a continuous linear model (module docstring).

    Parameters
    ----------
    model : TableStateSpace
        The model as the file gives it, internal units: inputs ``("u", "w")``
        (u [in], w [lbf]), outputs ``"z"`` [in/s**2] first, then any of ``"x"``
        [in], ``"v"`` [in/s], ``"dp"`` [psi]; A [1/s].  No delay added.
    loop_time : float
        Controller loop time [s] (0 only with ``delay="included"``: an analog loop).
    delay : str
        One of :data:`LTI_DELAYS`.
    kind : str
        One of :data:`KINDS` (where the model came from).
    pade_order : int
        Order of the Pade approximation (``delay="pade"``).
    allow_unstable : bool
        Accept poles of ``model`` in the closed right half plane.
    capacity : TableCapacity
        Stroke, velocity, stall force, moving mass and piston area, as far as
        the file states them (``[capacity]``; :mod:`.capacity`): what the
        virtual lab needs beside the model.

    Raises
    ------
    ConfigError
        Naming the key: ``delay``, ``kind``, ``loop_time``, ``pade_order``,
        ``outputs``/``inputs`` of the model, or ``allow_unstable`` for an
        unstable model.

    Examples
    --------
    >>> sys = StateSpace([[-100.0]], [[100.0, 0.5]], [[-100.0]], [[100.0, 0.25]],
    ...                  inputs=("u", "w"), outputs=("z",))
    >>> table = LTITable(TableStateSpace(sys), 5e-4, "first-order", "state-space")
    >>> table.tf("z", "u").relative_degree, round(table.dcgain("z", "w"), 12)
    (1, -0.25)
    """

    model: TableStateSpace
    loop_time: float
    delay: str
    kind: str = "state-space"
    pade_order: int = DEFAULT_PADE_ORDER
    allow_unstable: bool = False
    capacity: TableCapacity = field(default_factory=TableCapacity)

    def __post_init__(self):
        sys = self.model.system
        if self.kind not in KINDS:
            raise ConfigError("kind", "one of " + ", ".join(KINDS), self.kind)
        if self.delay not in LTI_DELAYS:
            raise ConfigError("delay", "one of " + ", ".join(LTI_DELAYS), self.delay)
        if not (np.isfinite(self.loop_time) and self.loop_time >= 0):
            raise ConfigError("loop_time", "a loop time >= 0 [s]", self.loop_time)
        if self.loop_time == 0 and self.delay != "included":
            raise ConfigError("loop_time", f"a positive loop time for delay = {self.delay!r}", 0.0)
        if isinstance(self.pade_order, bool) or not 1 <= int(self.pade_order) <= MAX_PADE_ORDER:
            raise ConfigError("pade_order", f"an integer from 1 to {MAX_PADE_ORDER}", self.pade_order)
        if sys.is_discrete:
            raise ConfigError("model", "a continuous model (dt = 0)", sys.dt)
        if sys.inputs != LTI_INPUTS or self.model.input_name != "u":
            raise ConfigError("inputs", "u and w, in that order", list(sys.inputs))
        outputs = sys.outputs
        if outputs[0] != "z" or not set(outputs) <= set(LTI_OUTPUTS) or len(set(outputs)) != len(outputs):
            raise ConfigError("outputs", "z first, then distinct ones of x, v, dp", list(outputs))
        if not self.allow_unstable:
            unstable = [p for p in self.model_poles() if p.real >= 0]
            if unstable:
                p = max(unstable, key=lambda q: q.real)
                raise ConfigError(
                    "allow_unstable",
                    "true to accept a table with poles in the closed right half plane",
                    f"a pole at {p.real:.6g}{p.imag:+.6g}j rad/s",
                )

    # ---------------------------------------------------------------- models
    @property
    def outputs(self) -> tuple[str, ...]:
        """The model's outputs (``"z"`` first)."""
        return self.model.system.outputs

    def state_space(self) -> TableStateSpace:
        """The file's model: continuous, inputs ``("u", "w")``, outputs ``"z"`` first, internal units, no delay added."""
        return self.model

    def design_state_space(self) -> TableStateSpace:
        """The model with the delay treatment (module docstring): what the design and :meth:`tf` use."""
        tau = self.loop_time
        if self.delay == "included":
            return self.model
        if self.delay == "pade":
            return command_delayed(self.model, pade_state_space(tau, int(self.pade_order)))
        return command_delayed(self.model, first_order_lag(tau))  # first-order; sampled designs with it

    def sampled_command(self, output: str = "z") -> StateSpace:
        """Exact sampled-data model of ``output`` per command u: ZOH over one loop, applied one loop late.

        Discrete (``dt = loop_time``), input ``u``, one more state than the
        model's u part (the command waiting one loop).  The model itself is
        used as given (``delay = "included"`` adds nothing but the hold).
        """
        if self.loop_time <= 0:
            raise ConfigError("loop_time", "a positive loop time for a sampled model", self.loop_time)
        part = self.model.system.reachable("u").channel(output, "u").zoh(self.loop_time)
        n = part.n_states
        A = np.block([[part.A, part.B], [np.zeros((1, n)), np.zeros((1, 1))]])
        B = np.concatenate([np.zeros((n, 1)), np.ones((1, 1))])
        C = np.hstack([part.C, part.D])
        return StateSpace(A, B, C, 0.0, self.loop_time, ("u",), (output,))

    # -------------------------------------------------------------- capacity
    # The names the virtual lab reads of any table (lab.lti_plant.virtual_table_for).
    @property
    def piston_area(self) -> float | None:
        """A_p [in**2] if stated (``[capacity] piston_area``)."""
        return self.capacity.piston_area

    @property
    def mass(self) -> float | None:
        """Moving mass [lbf*s**2/in] if stated (``[capacity] mass``)."""
        return self.capacity.mass

    @property
    def max_force(self) -> float | None:
        """Stall force [lbf] if stated (``[capacity] force``)."""
        return self.capacity.force

    # -------------------------------------------------------------- analysis
    def tf(self, output: str, input: str) -> TransferFunction:
        """Transfer function ``output/input`` of the design model [internal units, s in rad/s].

        The input's own part of the model (:meth:`StateSpace.reachable`)
        converted round-off safe (:meth:`TransferFunction.from_lti`), with
        pole-zero pairs closer than :data:`~impedance_mil.systems.CANCEL_RTOL`
        cancelled.
        """
        sys = self.design_state_space().system
        path = sys.reachable(sys.inputs[sys.input_index(input)]).channel(output, input)
        return TransferFunction.from_lti(path, cancel_rtol=CANCEL_RTOL)

    def has_force_path(self) -> bool:
        """Whether the test-article force w reaches the acceleration z (H_zw is not zero)."""
        return not self.tf("z", "w").is_zero

    def frequency_response(self, output: str, input: str, f_hz) -> np.ndarray:
        """Complex response of the design model at ``f_hz`` [Hz] (internal units)."""
        return self.design_state_space().frequency_response(output, input, f_hz)

    def dcgain(self, output: str, input: str) -> float:
        """Static gain of ``output/input`` (internal units; inf at a pole at the origin)."""
        return self.tf(output, input).dcgain()

    def model_poles(self) -> np.ndarray:
        """Poles [rad/s] of the file's model (a pole shared by the inputs' parts once)."""
        return _merged_poles(self.model.system)

    def poles(self) -> np.ndarray:
        """Poles [rad/s] of the design model (with the delay treatment's)."""
        return _merged_poles(self.design_state_space().system)

    def is_stable(self) -> bool:
        """Every pole of the design model in the open left half plane."""
        return bool(np.all(self.poles().real < 0))

    def summary(self) -> dict[str, Any]:
        """``imil table info`` of an LTI table: kind, loop time [s], delay, outputs, poles, DC gains.

        ``poles`` are the design model's (with the delay treatment's),
        ``model_poles`` the file's model's; ``dc_gains`` in internal units
        (``units`` names each, for :func:`impedance_mil.report.documents.express`).
        """
        gains = {f"{o}/{i}": self.dcgain(o, i) for o in self.outputs for i in LTI_INPUTS}
        model_poles = pole_table(self.model_poles())
        units = {
            f"dc_gains.{o}/{i}": f"({SIGNAL_UNITS[o]}) / ({SIGNAL_UNITS[i]})"
            for o in self.outputs
            for i in LTI_INPUTS
        }
        for k in range(len(model_poles)):
            units |= {f"model_poles[{k}].real": "rad/s", f"model_poles[{k}].imag": "rad/s"}
        return {
            "kind": self.kind,
            "loop_time": self.loop_time,
            "delay": self.delay,
            "outputs": list(self.outputs),
            "stable": self.is_stable(),
            "force_path": self.has_force_path(),
            "poles": pole_table(self.poles()),
            "model_poles": pole_table(self.model_poles()),
            "dc_gains": gains,
            "units": units,
        }

    # ------------------------------------------------------------ conversion
    @classmethod
    def from_control(
        cls,
        sys,
        loop_time: float,
        delay: str = "included",
        *,
        allow_unstable: bool = False,
        pade_order: int = DEFAULT_PADE_ORDER,
    ) -> LTITable:
        """A table from a continuous python-control ``StateSpace`` or ``TransferFunction``.

        ``sys`` is in the internal units with inputs named ``u`` [in] (and
        ``w`` [lbf]) and outputs ``z`` [in/s**2] (and any of ``x``, ``v``,
        ``dp``), as python-control names signals (``control.ss(...,
        inputs=["u", "w"], outputs=["z"])``); other signals are refused.  A
        transfer function is realized as :meth:`StateSpace.from_control` does
        (channel by channel).

        Parameters
        ----------
        sys : control.StateSpace or control.TransferFunction
        loop_time : float
            Controller loop time [s].
        delay : str
            One of :data:`LTI_DELAYS`; default ``"included"``.
        allow_unstable : bool
        pade_order : int
        """
        lti = StateSpace.from_control(sys)
        kind = "state-space" if lti.n_states == 0 or hasattr(sys, "A") else "transfer-function"
        return cls(table_system(lti), float(loop_time), delay, kind, pade_order, allow_unstable)

    def to_control(self):
        """The file's model (:meth:`state_space`) as a ``control.StateSpace``, signals named."""
        return self.model.system.to_control()

    def to_dict(self) -> dict[str, Any]:
        """Kind, loop time [s], delay and the model (``StateSpace.to_dict``, internal units)."""
        return {
            "kind": self.kind,
            "loop_time": self.loop_time,
            "delay": self.delay,
            "pade_order": int(self.pade_order),
            "allow_unstable": bool(self.allow_unstable),
            "capacity": self.capacity.to_dict(),
            "state_space": self.model.system.to_dict(),
        }


def _merged_poles(sys: StateSpace) -> np.ndarray:
    """The poles of each input's part of ``sys``, a pole of several parts once (relative :data:`SHARED_POLE_RTOL`)."""
    merged: list[complex] = []
    for name in sys.inputs:
        fresh = list(sys.reachable(name).poles())
        unmatched = list(merged)
        for p in fresh:
            hit = next(
                (k for k, q in enumerate(unmatched) if abs(p - q) <= SHARED_POLE_RTOL * max(abs(p), 1.0)),
                None,
            )
            if hit is None:
                merged.append(p)
            else:
                unmatched.pop(hit)
    return np.array(merged, dtype=complex)


def table_system(sys: StateSpace) -> TableStateSpace:
    """``sys`` with inputs ``u`` (and ``w``, a zero column when absent) and outputs ``z`` first."""
    unknown = [name for name in sys.inputs if name not in LTI_INPUTS]
    if unknown or "u" not in sys.inputs:
        raise ConfigError("inputs", "u and optionally w", list(sys.inputs))
    bad = [name for name in sys.outputs if name not in LTI_OUTPUTS]
    if bad or "z" not in sys.outputs:
        raise ConfigError("outputs", "z and optionally x, v, dp", list(sys.outputs))
    order = [sys.outputs.index(o) for o in LTI_OUTPUTS if o in sys.outputs]
    cols = [sys.input_index(i) if i in sys.inputs else None for i in LTI_INPUTS]
    B = np.column_stack([sys.B[:, j] if j is not None else np.zeros(sys.n_states) for j in cols])
    D = np.column_stack([sys.D[:, j] if j is not None else np.zeros(sys.n_outputs) for j in cols])
    out = StateSpace(
        sys.A,
        B,
        sys.C[order],
        D[order],
        0.0,
        LTI_INPUTS,
        tuple(sys.outputs[k] for k in order),
        sys.states,
    )
    return TableStateSpace(out, "u")
