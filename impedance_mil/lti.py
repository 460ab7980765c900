"""The one linear time-invariant (LTI) value object: a state space with named channels.

:class:`StateSpace` holds ``x' = A x + B u``, ``y = C x + D u`` (continuous,
``dt = 0``) or ``x[k+1] = A x[k] + B u[k]`` (discrete, sample time ``dt``
[s]), with named inputs, outputs and states.  Every model of the toolkit
that has matrices (the table of Eq 4-11/4-14, the sampled-data table, the
linearized nonlinear table, the specimens, the discrete controller) is
evaluated through it: one frequency response ``C (pI - A)^-1 B + D``, one
zero-order hold, one Tustin map, one state-space to polynomial conversion.

:class:`~impedance_mil.systems.TransferFunction` stays the object for the
design's algebra on improper transfer functions; it converts to and from
this one (``TransferFunction.from_lti``, ``TransferFunction.to_lti``).

Units: frequencies are in Hz at the interface (:meth:`StateSpace.frequency_response`)
and in rad/s inside the matrices of a continuous system (``A`` [1/s]); the
sample time is in seconds.

Examples
--------
>>> import numpy as np
>>> sys = StateSpace([[-2.0]], [[2.0]], [[1.0]], 0.0, inputs=("u",), outputs=("y",))
>>> round(float(sys.dcgain()), 12)
1.0
>>> round(float(abs(sys.frequency_response(2.0 / (2 * np.pi))) ** 2), 12)  # |2/(2j + 2)|^2
0.5
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .errors import ConfigError, ImproperSystemError
from .lazy import LazyModule
from .units import TWO_PI

#: python-control and scipy, imported on first use (:class:`~impedance_mil.lazy.LazyModule`): only
#: the conversions and the discretization need them, and a command that only reads a configuration
#: should not wait 2 s for them (issue 16, start-up).
control = LazyModule("control")
scipy_linalg = LazyModule("scipy.linalg")
scipy_signal = LazyModule("scipy.signal")

#: Frequency points solved per batch by :meth:`StateSpace.evaluate` (bounds the memory of the batch).
BATCH_POINTS = 2048


def _names(given: Sequence[str], count: int, prefix: str, key: str) -> tuple[str, ...]:
    if not given:
        return tuple(f"{prefix}{i}" for i in range(count))
    names = tuple(str(g) for g in given)
    if len(names) != count or len(set(names)) != count:
        raise ConfigError(key, f"{count} distinct names", list(names))
    return names


def _matrices(A, B, C, D) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Coerce ``(A, B, C, D)`` to 2-D float arrays: vectors are one input (B) or one output (C)."""
    A = np.asarray(A, dtype=float)
    A = np.zeros((0, 0)) if A.size == 0 else np.atleast_2d(A)
    n = A.shape[0]
    D = np.asarray(D, dtype=float)
    p_d, m_d = D.shape if D.ndim == 2 else (1, 1)
    B = np.asarray(B, dtype=float)
    C = np.asarray(C, dtype=float)
    try:
        if B.ndim < 2:
            B = B.reshape(n, 1) if n else np.zeros((0, m_d))
        if C.ndim < 2:
            C = C.reshape(1, n) if n else np.zeros((p_d, 0))
        p, m = C.shape[0], B.shape[1]
        if D.ndim < 2:
            D = np.full((p, m), float(D.ravel()[0])) if D.size == 1 else D.reshape(p, m)
        if A.shape != (n, n) or B.shape[0] != n or C.shape[1] != n or D.shape != (p, m):
            raise ValueError("inconsistent shapes")
    except (ValueError, IndexError):
        raise ConfigError(
            "state_space",
            "A (n x n), B (n x m), C (p x n) and D (p x m) of matching sizes",
            f"A {A.shape}, B {B.shape}, C {C.shape}, D {D.shape}",
        ) from None
    return A, B, C, D


@dataclass(frozen=True, eq=False, init=False)
class StateSpace:
    """A linear time-invariant system ``(A, B, C, D)`` with sample time and channel names.

    Parameters
    ----------
    A : array_like, shape (n, n)
        State matrix ([1/s] for a continuous system; dimensionless for a discrete one).
    B : array_like, shape (n, m)
        Input matrix; a vector of n entries is one input.
    C : array_like, shape (p, n)
        Output matrix; a vector of n entries is one output.
    D : array_like, shape (p, m)
        Feedthrough; a scalar for a SISO system.
    dt : float
        Sample time [s]; 0 for a continuous system.
    inputs, outputs, states : sequence of str, optional
        Names (default ``u0, u1 ...``, ``y0 ...``, ``x0 ...``), e.g. ``("u", "w")``
        and ``("z", "x", "v", "dp")`` for the table of Eq 4-11.

    Raises
    ------
    ConfigError
        Inconsistent shapes, non-finite entries, a negative or non-finite
        sample time, or names that do not match the dimensions.

    Examples
    --------
    >>> sys = StateSpace([[0.0, 1.0], [-4.0, -0.4]], [[0.0], [1.0]], [[1.0, 0.0]], 0.0)
    >>> sys.n_states, sys.n_inputs, sys.n_outputs
    (2, 1, 1)
    >>> [round(float(abs(p)), 6) for p in sys.poles()]
    [2.0, 2.0]
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    dt: float
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    states: tuple[str, ...]

    def __init__(
        self,
        A: ArrayLike,
        B: ArrayLike,
        C: ArrayLike,
        D: ArrayLike = 0.0,
        dt: float = 0.0,
        inputs: Sequence[str] = (),
        outputs: Sequence[str] = (),
        states: Sequence[str] = (),
    ):
        A, B, C, D = _matrices(A, B, C, D)
        n, m, p = A.shape[0], B.shape[1], C.shape[0]
        if not all(np.all(np.isfinite(M)) for M in (A, B, C, D)):
            raise ConfigError("state_space", "finite matrices")
        if not (np.isfinite(dt) and dt >= 0):
            raise ConfigError("dt", "a sample time >= 0 [s] (0: continuous)", dt)
        for name, M in (("A", A), ("B", B), ("C", C), ("D", D)):
            # The caller's arrays are copied, not frozen; read-only ones (another value's) are shared.
            M = np.array(M, order="C") if M.flags.writeable or not M.flags.c_contiguous else M
            M.setflags(write=False)
            object.__setattr__(self, name, M)
        object.__setattr__(self, "dt", float(dt))
        object.__setattr__(self, "inputs", _names(inputs, m, "u", "inputs"))
        object.__setattr__(self, "outputs", _names(outputs, p, "y", "outputs"))
        object.__setattr__(self, "states", _names(states, n, "x", "states"))

    # ------------------------------------------------------------- properties
    @property
    def n_states(self) -> int:
        """Number of states n."""
        return self.A.shape[0]

    @property
    def n_inputs(self) -> int:
        """Number of inputs m."""
        return self.B.shape[1]

    @property
    def n_outputs(self) -> int:
        """Number of outputs p."""
        return self.C.shape[0]

    @property
    def is_discrete(self) -> bool:
        """True for a sampled system (``dt > 0``)."""
        return self.dt > 0

    @property
    def is_siso(self) -> bool:
        """One input and one output."""
        return self.n_inputs == 1 and self.n_outputs == 1

    # -------------------------------------------------------------- channels
    def input_index(self, name: str) -> int:
        """Position of the input ``name``; :class:`ConfigError` naming the known inputs."""
        if name not in self.inputs:
            raise ConfigError("input", "one of " + ", ".join(self.inputs), name)
        return self.inputs.index(name)

    def output_index(self, name: str) -> int:
        """Position of the output ``name``; :class:`ConfigError` naming the known outputs."""
        if name not in self.outputs:
            raise ConfigError("output", "one of " + ", ".join(self.outputs), name)
        return self.outputs.index(name)

    def channel(self, output: str, input: str) -> StateSpace:
        """The SISO system from the input named ``input`` to the output named ``output``.

        The states are kept as they are (no reduction): the poles are those of ``A``.
        """
        i, j = self.output_index(output), self.input_index(input)
        return StateSpace(
            self.A,
            self.B[:, j : j + 1],
            self.C[i : i + 1, :],
            self.D[i : i + 1, j : j + 1],
            self.dt,
            (input,),
            (output,),
            self.states,
        )

    def reachable(self, input: str) -> StateSpace:
        """The states structurally reachable from the input named ``input``, with every input and output.

        A state is kept when a chain of nonzero entries of ``B[:, j]`` and
        ``A`` leads to it from input j; the others are removed by deleting
        their rows and columns (exact: no similarity, so structural zeros and
        the Markov parameters stay exact).  The response from ``input`` is
        unchanged.  For a model realized input by input (the
        transfer-function tables of :mod:`impedance_mil.plant.lti_table`)
        this is the part of that input, without the other inputs' copies of
        shared poles.
        """
        j = self.input_index(input)
        pattern = self.A != 0
        keep = self.B[:, j] != 0
        while True:
            grown = keep | pattern[:, keep].any(axis=1)
            if (grown == keep).all():
                break
            keep = grown
        idx = np.flatnonzero(keep)
        return StateSpace(
            self.A[np.ix_(idx, idx)],
            self.B[idx, :],
            self.C[:, idx],
            self.D,
            self.dt,
            self.inputs,
            self.outputs,
            tuple(self.states[i] for i in idx),
        )

    # -------------------------------------------------------------- evaluate
    def evaluate(self, points) -> np.ndarray:
        """``C (pI - A)^-1 B + D`` at complex points p (s [rad/s] or z), by a linear solve per point.

        No polynomial is formed, so lightly damped, widely spaced modes keep
        full precision.  The solves are batched (LU per point, as
        ``numpy.linalg.solve``).

        Parameters
        ----------
        points : array_like of complex
            Evaluation points (s for a continuous system, z for a discrete one).

        Returns
        -------
        ndarray of complex
            Shape of ``points`` for a SISO system, ``(p, m) + shape`` otherwise.
            A point on an eigenvalue of ``A`` gives ``inf``.
        """
        pts = np.asarray(points, dtype=complex)
        flat = pts.reshape(-1)
        p, m, n = self.n_outputs, self.n_inputs, self.n_states
        out = np.empty((flat.size, p, m), dtype=complex)
        out[:] = self.D
        eye = np.eye(n)
        for start in range(0, flat.size if n else 0, BATCH_POINTS):
            chunk = flat[start : start + BATCH_POINTS]
            pencil = chunk[:, None, None] * eye - self.A
            out[start : start + chunk.size] += _resolvent(pencil, self.B, self.C)
        res = np.moveaxis(out, 0, -1).reshape((p, m) + pts.shape)
        return res[0, 0] if self.is_siso else res

    def frequency_response(self, f_hz) -> np.ndarray:
        """Complex response at frequencies ``f_hz`` [Hz].

        ``s = j 2 pi f`` for a continuous system, ``z = exp(j 2 pi f dt)`` for
        a discrete one.  Shape of ``f_hz`` for a SISO system, ``(p, m) +
        shape`` otherwise; select a channel with :meth:`channel`.
        """
        f = np.asarray(f_hz, dtype=float)
        w = TWO_PI * f
        return self.evaluate(np.exp(1j * w * self.dt) if self.is_discrete else 1j * w)

    def poles(self) -> np.ndarray:
        """Eigenvalues of ``A`` (s-plane [rad/s] or z-plane)."""
        return np.linalg.eigvals(self.A) if self.n_states else np.zeros(0, complex)

    def is_stable(self) -> bool:
        """Every pole in the open left half plane (inside the unit circle for a discrete system)."""
        p = self.poles()
        return bool(np.all(np.abs(p) < 1.0)) if self.is_discrete else bool(np.all(p.real < 0.0))

    def dcgain(self):
        """Static gain: the response at s = 0 (z = 1); ``inf`` where ``A`` has a pole there.

        A float for a SISO system, a (p, m) array otherwise.
        """
        g = self.evaluate(1.0 if self.is_discrete else 0.0)
        return float(g.real) if self.is_siso else g.real

    # --------------------------------------------------------- discretization
    def _require_continuous(self, what: str) -> None:
        if self.is_discrete:
            raise ConfigError(what, "a continuous system (dt = 0)", f"dt = {self.dt}")

    def zoh(self, dt: float) -> StateSpace:
        """Exact zero-order-hold discretization over the sample time ``dt`` [s].

        ``Phi = exp(A dt)`` and ``Gamma = int_0^dt exp(A t) dt B`` from one
        matrix exponential of the block matrix ``[[A, B], [0, 0]] dt``; ``C``
        and ``D`` are unchanged, so the discrete system reproduces the
        continuous response to a held input exactly at the samples.
        """
        self._require_continuous("zoh")
        if not (np.isfinite(dt) and dt > 0):
            raise ConfigError("dt", "a positive sample time [s]", dt)
        n, m = self.n_states, self.n_inputs
        block = np.zeros((n + m, n + m))
        block[:n, :n] = self.A * dt
        block[:n, n:] = self.B * dt
        E = scipy_linalg.expm(block)
        return StateSpace(E[:n, :n], E[:n, n:], self.C, self.D, dt, self.inputs, self.outputs, self.states)

    def tustin(self, dt: float, prewarp_hz: float | None = None) -> StateSpace:
        """Bilinear (Tustin) discretization ``s = c (z - 1)/(z + 1)`` over ``dt`` [s].

        ``c = 2/dt``, or ``c = w_p / tan(w_p dt/2)`` with ``w_p = 2 pi prewarp_hz``
        so that the discrete response at ``prewarp_hz`` [Hz] equals the
        continuous one exactly (report Section 6.5, Step 4).  With
        ``M = (I - A/c)^-1``: ``A_d = M (I + A/c)``, ``B_d = (2/c) M B``,
        ``C_d = C M``, ``D_d = D + C M B / c``.
        """
        self._require_continuous("tustin")
        if not (np.isfinite(dt) and dt > 0):
            raise ConfigError("dt", "a positive sample time [s]", dt)
        if prewarp_hz is None:
            c = 2.0 / dt
        else:
            if not 0 < prewarp_hz < 0.5 / dt:
                raise ConfigError("prewarp_hz", f"a frequency in (0, {0.5 / dt:g}) Hz", prewarp_hz)
            wp = TWO_PI * prewarp_hz
            c = wp / np.tan(wp * dt / 2.0)
        n = self.n_states
        lhs = np.eye(n) - self.A / c
        Ad = np.linalg.solve(lhs, np.eye(n) + self.A / c)
        MB = np.linalg.solve(lhs, self.B)
        Cd = np.linalg.solve(lhs.T, self.C.T).T
        return StateSpace(
            Ad, (2.0 / c) * MB, Cd, self.D + self.C @ MB / c, dt, self.inputs, self.outputs, self.states
        )

    # ------------------------------------------------------------ conversion
    def shape_text(self) -> str:
        """``"p outputs x m inputs, n states"`` (for messages)."""
        return f"{self.n_outputs} outputs x {self.n_inputs} inputs, {self.n_states} states"

    @classmethod
    def from_polynomials(cls, num, den, dt: float = 0.0, input: str = "u0", output: str = "y0") -> StateSpace:
        """Controllable-canonical realization of a proper ``num/den`` (descending powers of s or z).

        Raises
        ------
        ImproperSystemError
            ``num/den`` is improper (more zeros than poles).
        """
        num = np.trim_zeros(np.atleast_1d(np.asarray(num, dtype=float)), "f")
        den = np.trim_zeros(np.atleast_1d(np.asarray(den, dtype=float)), "f")
        if den.size == 0:
            raise ConfigError("den", "a non-zero denominator", den.tolist())
        num = num if num.size else np.zeros(1)
        if num.size > den.size:
            raise ImproperSystemError(
                f"an improper transfer function (relative degree {den.size - num.size}) has no "
                "state-space realization"
            )
        if den.size == 1:
            return cls(
                np.zeros((0, 0)),
                np.zeros((0, 1)),
                np.zeros((1, 0)),
                num[-1] / den[0],
                dt,
                (input,),
                (output,),
            )
        A, B, C, D = scipy_signal.tf2ss(num, den)
        return cls(A, B, C, D, dt, (input,), (output,))

    @classmethod
    def from_control(cls, sys) -> StateSpace:
        """Convert a python-control ``StateSpace`` or ``TransferFunction`` (SISO or MIMO).

        Names and the sample time are kept (python-control's ``dt = None``,
        the unspecified time base, is read as continuous).  A MIMO transfer
        function is realized channel by channel (no slycot needed): the
        result is not minimal.

        Raises
        ------
        ConfigError
            Not a python-control LTI object, or a discrete system with
            unspecified sample time (``dt = True``).
        """
        if not isinstance(sys, (control.StateSpace, control.TransferFunction)):
            raise ConfigError(
                "system", "a control.StateSpace or control.TransferFunction", type(sys).__name__
            )
        if sys.dt is True:
            raise ConfigError(
                "dt", "a numeric sample time [s] (python-control dt=True is unspecified)", sys.dt
            )
        dt = float(sys.dt or 0.0)
        if isinstance(sys, control.StateSpace):
            return cls(
                sys.A,
                sys.B,
                sys.C,
                sys.D,
                dt,
                tuple(sys.input_labels),
                tuple(sys.output_labels),
                tuple(sys.state_labels),
            )
        parts = [
            [cls.from_polynomials(sys.num[i][j], sys.den[i][j], dt) for j in range(sys.ninputs)]
            for i in range(sys.noutputs)
        ]
        return _assemble(parts, dt, tuple(sys.input_labels), tuple(sys.output_labels))

    def to_control(self):
        """As a ``control.StateSpace`` with the same names and sample time."""
        return control.ss(
            self.A,
            self.B,
            self.C,
            self.D,
            self.dt,
            inputs=list(self.inputs),
            outputs=list(self.outputs),
            states=list(self.states),
        )

    def to_dict(self) -> dict:
        """Plain lists and names (for result files)."""
        return {
            "A": self.A.tolist(),
            "B": self.B.tolist(),
            "C": self.C.tolist(),
            "D": self.D.tolist(),
            "dt": self.dt,
            "inputs": list(self.inputs),
            "outputs": list(self.outputs),
            "states": list(self.states),
        }

    def __repr__(self) -> str:
        kind = f"dt={self.dt:g} s" if self.is_discrete else "continuous"
        return f"StateSpace({self.shape_text()}, {kind}, inputs={list(self.inputs)}, outputs={list(self.outputs)})"


def _resolvent(pencil: np.ndarray, B: np.ndarray, C: np.ndarray) -> np.ndarray:
    """``C pencil[k]^-1 B`` for each k; a singular pencil (a point on a pole) gives ``inf``."""
    rhs = np.broadcast_to(B.astype(complex), (pencil.shape[0],) + B.shape)
    try:
        return C @ np.linalg.solve(pencil, rhs)
    except np.linalg.LinAlgError:
        out = np.empty((pencil.shape[0], C.shape[0], B.shape[1]), dtype=complex)
        for k in range(pencil.shape[0]):
            try:
                out[k] = C @ np.linalg.solve(pencil[k], rhs[k])
            except np.linalg.LinAlgError:
                out[k] = np.inf
        return out


def _assemble(parts: list[list[StateSpace]], dt: float, inputs, outputs) -> StateSpace:
    """Block-diagonal MIMO system whose channel (i, j) is ``parts[i][j]`` (SISO)."""
    p, m = len(parts), len(parts[0])
    sizes = [s.n_states for row in parts for s in row]
    n = sum(sizes)
    A, B, C, D = np.zeros((n, n)), np.zeros((n, m)), np.zeros((p, n)), np.zeros((p, m))
    k = 0
    for i, row in enumerate(parts):
        for j, s in enumerate(row):
            q = s.n_states
            A[k : k + q, k : k + q] = s.A
            B[k : k + q, j] = s.B[:, 0]
            C[i, k : k + q] = s.C[0]
            D[i, j] = s.D[0, 0]
            k += q
    return StateSpace(A, B, C, D, dt, inputs, outputs)
