"""Time discretization of the MIL controller (report Section 6.5, Steps 3-5).

:func:`discretize` turns the pair of proper continuous controller terms
``(H_uz, H_uw)`` of the standardized controller ``u = H_uz z_vs + H_uw w``
(Eq. 6-7 with the filters of Step 2; ``H_uw`` carries its sign) into a
:class:`DiscreteController`: one structured state-space realization per
channel at the controller loop time.

Realization (see :mod:`impedance_mil.implement.realization`): a cascade of
first- and second-order sections whose eigenvalues are stored exactly (the
double pole of ``H_uz`` at s = 0 becomes the Jordan block ``[[1, 1], [0, 1]]``
at z = 1).  The runtime and the generated code update the states in *delta
form* with compensated (Kahan) summation,

    x[k+1] = x[k] + ((A - I) x[k] + B v[k]),

so that single-precision arithmetic keeps the integrators of ``H_uz`` within
~1e-7 of the double-precision trajectory over minutes of loop time, where
plain single-precision accumulation drifts by ~1e-3 (measured in
``tests/implement/test_discretize.py``).

The double pole at z = 1 means the displacement command ``u`` is the double
integral of ``z_vs``: any offset in ``z_vs`` (load-cell bias divided by the
VS mass, a ground motion without baseline correction) makes ``u`` drift
quadratically.  ``leak_hz`` moves both poles from s = 0 to
``s = -2*pi*leak_hz`` (a second-order high-pass on the displacement
command), which bounds the drift at the cost of a low-frequency error of
about ``2*leak_hz/f`` in phase [rad] at frequency ``f``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..design.sampling import check_implementable_fc
from ..errors import ConfigError, UnstableDesignError
from ..lti import StateSpace
from ..systems import TransferFunction
from ..units import TWO_PI
from .realization import (
    METHODS,
    DiscreteZPK,
    Section,
    canonical_realization,
    cascade,
    continuous_zpk,
    discrete_zpk,
    sections_from_zpk,
)

#: Realizations offered by :func:`discretize`.
REALIZATIONS = ("sections", "canonical")


@dataclass(frozen=True, eq=False)
class ChannelRealization:
    """Discrete state-space realization of one controller channel.

    ``x[k+1] = A x[k] + B v[k]``, ``y[k] = C x[k] + D v[k]`` with input ``v``
    (``z_vs`` [in/s**2] for H_uz, ``w`` [lbf] for H_uw) and output [in].

    Attributes
    ----------
    name : str
        ``"H_uz"`` or ``"H_uw"``.
    A, B, C : ndarray
        float64 matrices, shapes (n, n), (n,), (n,).
    D : float
        Feed-through [in per input unit].
    continuous : TransferFunction
        The continuous transfer function that was discretized (after any leak).
    zpk : DiscreteZPK
        Its discrete poles, zeros and gain.
    sections : tuple of Section
        The cascade, input side first (empty for the canonical realization).
    n_integrators : int
        Number of poles exactly at z = 1.
    """

    name: str
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: float
    continuous: TransferFunction
    zpk: DiscreteZPK
    sections: tuple
    n_integrators: int

    @property
    def n_states(self) -> int:
        """Number of states."""
        return int(self.B.size)

    def system_matrix(self) -> np.ndarray:
        """``[[A - I, B], [C, D]]`` (float64), the layout the kernels use."""
        n = self.n_states
        m = np.zeros((n + 1, n + 1))
        m[:n, :n] = self.A - np.eye(n)
        m[:n, n] = self.B
        m[n, :n] = self.C
        m[n, n] = self.D
        return m

    @property
    def system(self) -> StateSpace:
        """The realization as a discrete :class:`~impedance_mil.lti.StateSpace` (sample time the loop time)."""
        inp = "z_vs" if self.name == "H_uz" else "w"
        return StateSpace(self.A, self.B, self.C, self.D, self.zpk.loop_time_s, (inp,), ("u",))

    def frequency_response(self, f_hz) -> np.ndarray:
        """Complex response of the realization at ``f_hz`` [Hz] (``z = exp(j 2 pi f T)``)."""
        return self.system.frequency_response(np.atleast_1d(np.asarray(f_hz, float)))


@dataclass(frozen=True, eq=False)
class DiscreteController:
    """The discrete MIL controller ``u = H_uz z_vs + H_uw w`` (Section 6.5, Step 5).

    Attributes
    ----------
    z, w : ChannelRealization
        The H_uz (input z_vs [in/s**2]) and H_uw (input w [lbf]) channels.
    loop_time_s : float
        Controller loop time [s].
    method : str
        ``"tustin"``, ``"zoh"`` or ``"matched"``.
    prewarp_hz : float or None
        Tustin pre-warping frequency [Hz].
    fc_hz : float or None
        Filter cut-off frequency [Hz] of the design.
    leak_hz : float or None
        Corner [Hz] of the leak that replaced the double integrator, if any.
    realization : str
        ``"sections"`` (structured cascade) or ``"canonical"`` (comparison only).
    source : dict
        Where the controller came from (design file fields, free form).
    """

    z: ChannelRealization
    w: ChannelRealization
    loop_time_s: float
    method: str
    prewarp_hz: float | None
    fc_hz: float | None
    leak_hz: float | None
    realization: str
    source: Mapping[str, Any] = field(default_factory=dict)

    @property
    def channels(self) -> tuple[ChannelRealization, ChannelRealization]:
        """``(z, w)``."""
        return (self.z, self.w)

    def frequency_response(self, f_hz) -> tuple[np.ndarray, np.ndarray]:
        """Discrete responses of H_uz and H_uw at ``f_hz`` [Hz]."""
        return self.z.frequency_response(f_hz), self.w.frequency_response(f_hz)

    def info(self) -> dict:
        """Plain summary (method, loop time, orders, integrators, sections)."""
        return {
            "loop_time_s": self.loop_time_s,
            "method": self.method,
            "prewarp_hz": self.prewarp_hz,
            "fc_hz": self.fc_hz,
            "leak_hz": self.leak_hz,
            "realization": self.realization,
            "channels": {
                ch.name: {
                    "n_states": ch.n_states,
                    "n_integrators": ch.n_integrators,
                    "sections": [s.form for s in ch.sections],
                }
                for ch in self.channels
            },
        }


def with_leak(tf: TransferFunction, leak_hz: float) -> TransferFunction:
    """Move every pole at s = 0 of ``tf`` to ``s = -2*pi*leak_hz``.

    For ``H_uz`` (double pole at the origin) this is ``H_uz * s**2/(s + w_l)**2``:
    the displacement command passes a second-order high-pass at ``leak_hz`` [Hz].
    """
    if not leak_hz > 0:
        raise ConfigError("leak_hz", "a positive frequency [Hz]", leak_hz)
    _, _, _, n0 = continuous_zpk(tf)
    if n0 == 0:
        return tf
    den = np.asarray(tf.den, float)[: tf.den.size - n0]
    den = np.polymul(den, np.real(np.poly(np.full(n0, -TWO_PI * leak_hz))))
    return TransferFunction(tf.num, den)


def _check(tf: TransferFunction, name: str, loop_time_s: float) -> None:
    if not tf.is_proper:
        raise ConfigError(
            name,
            "a proper transfer function (apply the filters of Step 2)",
            f"relative degree {tf.relative_degree}",
        )
    _, poles, _, _ = continuous_zpk(tf)
    if np.any(poles.real > 0):
        raise UnstableDesignError(
            f"{name} has poles in the right half plane: {np.round(poles[poles.real > 0], 3).tolist()} rad/s"
        )
    if np.any(np.abs(poles) * loop_time_s > np.pi):
        raise ConfigError(
            f"{name} poles",
            "all below the Nyquist frequency of the loop",
            f"{np.max(np.abs(poles)) / TWO_PI:.1f} Hz",
        )


def _channel(name, tf, dt, method, prewarp_hz, realization, norm_hz) -> ChannelRealization:
    zpk = discrete_zpk(tf, dt, method=method, prewarp_hz=prewarp_hz)
    n1 = int(np.sum(zpk.poles == 1.0))
    if realization == "sections":
        sections = tuple(sections_from_zpk(zpk, norm_hz))
        A, B, C, D = cascade(list(sections))
    else:
        sections = ()
        A, B, C, D = canonical_realization(zpk)
    return ChannelRealization(name, A, B, C, D, tf, zpk, sections, n1)


def discretize(
    H_uz: TransferFunction,
    H_uw: TransferFunction,
    loop_time_s: float,
    *,
    method: str = "tustin",
    prewarp_hz: float | None = None,
    fc_hz: float | None = None,
    leak_hz: float | None = None,
    realization: str = "sections",
    source: Mapping[str, Any] | None = None,
) -> DiscreteController:
    """Discretize the standardized MIL controller (report Section 6.5, Steps 4-5).

    Parameters
    ----------
    H_uz : TransferFunction
        Filtered ``F_z / H_zu`` [in per in/s**2]; proper, may have poles at s = 0.
    H_uw : TransferFunction
        Filtered ``-F_w H_zw / H_zu`` [in/lbf] (carries its sign, so ``u = u_z + u_w``).
    loop_time_s : float
        Controller loop time [s] (Table 4.1: 500e-6).
    method : {"tustin", "zoh", "matched"}
        Discretization; Tustin is the report's (Step 4).
    prewarp_hz : float, optional
        Tustin pre-warping frequency [Hz], e.g. ``fc_hz``.
    fc_hz : float, optional
        Cut-off [Hz] of the design's filters; must lie below the Nyquist
        frequency ``1/(2*loop_time_s)``.
    leak_hz : float, optional
        Replace the double integrator of ``H_uz`` by a leak at this corner [Hz]
        (bounds the drift of the displacement command; see the module notes).
    realization : {"sections", "canonical"}
        Structured cascade (default) or controllable canonical (comparison only).
    source : mapping, optional
        Provenance recorded in the result (e.g. design-file fields).

    Returns
    -------
    DiscreteController

    Examples
    --------
    >>> from impedance_mil.systems import TransferFunction
    >>> H = TransferFunction([1.0], [1.0, 100.0])
    >>> dc = discretize(H, H, 0.0005)
    >>> dc.z.n_states, dc.method
    (1, 'tustin')
    """
    if not (isinstance(loop_time_s, (int, float)) and loop_time_s > 0):
        raise ConfigError("loop_time_s", "a positive loop time [s]", loop_time_s)
    nyquist = 0.5 / loop_time_s
    for key, f in (("fc_hz", fc_hz), ("prewarp_hz", prewarp_hz)):
        if f is not None:
            check_implementable_fc(key, f, loop_time_s)
    if method not in METHODS:
        raise ConfigError("method", f"one of {', '.join(METHODS)}", method)
    if realization not in REALIZATIONS:
        raise ConfigError("realization", f"one of {', '.join(REALIZATIONS)}", realization)
    if leak_hz is not None:
        H_uz = with_leak(H_uz, leak_hz)
        H_uw = with_leak(H_uw, leak_hz)
    _check(H_uz, "H_uz", loop_time_s)
    _check(H_uw, "H_uw", loop_time_s)
    # Sections are normalised to unit gain at a frequency inside the pass band.
    norm_hz = 0.25 * (fc_hz if fc_hz is not None else 0.1 * nyquist)
    z = _channel("H_uz", H_uz, loop_time_s, method, prewarp_hz, realization, norm_hz)
    w = _channel("H_uw", H_uw, loop_time_s, method, prewarp_hz, realization, norm_hz)
    return DiscreteController(
        z, w, float(loop_time_s), method, prewarp_hz, fc_hz, leak_hz, realization, dict(source or {})
    )


__all__ = ["ChannelRealization", "DiscreteController", "Section", "discretize", "with_leak"]
