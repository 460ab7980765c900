"""The ground-motion value object: scaling, resampling, baseline correction, integration.

A :class:`GroundMotion` is a uniformly sampled acceleration history in the
internal unit (in/s**2), read as **piecewise linear** between samples (the
same reading the exact response-spectrum recurrence of
:mod:`impedance_mil.signals.spectrum` uses).  Every operation returns a new
object; nothing is modified in place.

Report Section 8.2 (Table 8.1): the seed records are *time-scaled by a factor
of 2* (time compressed, t' = t/2, the same accelerations) and amplitude-scaled
to a target PGA, e.g. Imperial Valley-02 (El Centro, RSN 6) from 0.28 g to
0.8 g.  In this module that is ``motion.time_scaled(2.0).scaled_to_pga(0.8)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from ..bounds import MAX_RECORD_SAMPLES, check_count
from ..errors import ConfigError
from ..lazy import LazyModule
from ..units import G0

#: scipy.signal, imported on first use: only resampling needs it (issue 16, start-up).
scipy_signal = LazyModule("scipy.signal")

#: Largest up or down factor accepted for rational resampling.
MAX_RESAMPLE_FACTOR = 1000

#: Relative tolerance on a resampling ratio written as a fraction.
RESAMPLE_RATIO_RTOL = 1e-9


def _positive(key: str, value: float) -> float:
    number = float(value)
    if not (math.isfinite(number) and number > 0.0):
        raise ConfigError(key, "a positive finite number", value)
    return number


def integrate_piecewise_linear(accel: np.ndarray, time_step: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact velocity and displacement of a piecewise-linear acceleration from rest.

    Parameters
    ----------
    accel : ndarray
        Acceleration samples [in/s**2] (any consistent unit works).
    time_step : float
        Sample interval [s].

    Returns
    -------
    velocity, displacement : ndarray
        [in/s] and [in], zero at the first sample.  Velocity is the trapezoidal
        sum; displacement adds ``dt**2 * (2 a_k + a_{k+1}) / 6`` per step, which
        is exact when the acceleration is linear between samples.
    """
    a = np.asarray(accel, dtype=float)
    dt = float(time_step)
    dv = 0.5 * dt * (a[:-1] + a[1:])
    vel = np.concatenate(([0.0], np.cumsum(dv)))
    dd = dt * vel[:-1] + dt * dt * (2.0 * a[:-1] + a[1:]) / 6.0
    disp = np.concatenate(([0.0], np.cumsum(dd)))
    return vel, disp


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """A uniformly sampled ground acceleration history.

    Parameters
    ----------
    time_step : float
        Sample interval [s], positive.
    accel : ndarray
        Acceleration samples [in/s**2], finite, at least two.  Stored as a
        read-only float copy.
    name : str
        Short label (e.g. ``"Imperial Valley-02 El Centro 180"``).
    source : str
        Where the samples came from and what was done to them.

    Examples
    --------
    >>> from impedance_mil.signals import builtin_motion
    >>> gm1 = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    >>> round(gm1.pga_g, 6), round(gm1.time_step, 4)
    (0.8, 0.005)
    """

    time_step: float
    accel: np.ndarray = field(repr=False)
    name: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "time_step", _positive("time_step", self.time_step))
        check_count("accel", np.size(self.accel), MAX_RECORD_SAMPLES, "samples in a record")
        values = np.array(self.accel, dtype=float, copy=True)
        if values.ndim != 1 or values.size < 2:
            raise ConfigError("accel", "a 1-D array of at least 2 samples", f"shape {values.shape}")
        if not np.all(np.isfinite(values)):
            bad = int(np.flatnonzero(~np.isfinite(values))[0])
            raise ConfigError("accel", "finite samples", f"non-finite value at sample {bad}")
        values.setflags(write=False)
        object.__setattr__(self, "accel", values)

    # ------------------------------------------------------------------ views
    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.accel.size)

    @property
    def time(self) -> np.ndarray:
        """Sample times [s], starting at 0."""
        return np.arange(self.npts) * self.time_step

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return (self.npts - 1) * self.time_step

    @property
    def pga(self) -> float:
        """Peak absolute acceleration [in/s**2]."""
        return float(np.max(np.abs(self.accel)))

    @property
    def pga_g(self) -> float:
        """Peak absolute acceleration [g]."""
        return self.pga / G0

    def velocity(self) -> np.ndarray:
        """Ground velocity [in/s] from rest, exact for piecewise-linear acceleration."""
        return integrate_piecewise_linear(self.accel, self.time_step)[0]

    def displacement(self) -> np.ndarray:
        """Ground displacement [in] from rest, exact for piecewise-linear acceleration."""
        return integrate_piecewise_linear(self.accel, self.time_step)[1]

    @property
    def pgv(self) -> float:
        """Peak absolute velocity [in/s] of the motion as given (no baseline correction)."""
        return float(np.max(np.abs(self.velocity())))

    @property
    def pgd(self) -> float:
        """Peak absolute displacement [in] of the motion as given (no baseline correction)."""
        return float(np.max(np.abs(self.displacement())))

    # -------------------------------------------------------------- transforms
    def _derived(self, time_step: float, accel: np.ndarray, note: str) -> GroundMotion:
        source = f"{self.source}; {note}" if self.source else note
        return GroundMotion(time_step, accel, self.name, source)

    def scaled(self, factor: float) -> GroundMotion:
        """Multiply every acceleration by ``factor`` (dimensionless, non-zero)."""
        number = float(factor)
        if not math.isfinite(number) or number == 0.0:
            raise ConfigError("scale factor", "a finite non-zero number", factor)
        return self._derived(self.time_step, self.accel * number, f"amplitude x{number:.6g}")

    def scaled_to_pga(self, pga_g: float) -> GroundMotion:
        """Amplitude-scale so that the peak absolute acceleration is ``pga_g`` [g].

        Report Table 8.1 scales the seed records to 0.8, 0.6 and 0.4 g.

        Raises
        ------
        ConfigError
            ``pga_g`` not positive, or the motion is identically zero.
        """
        target = _positive("pga", pga_g)
        if self.pga == 0.0:
            raise ConfigError("pga", "a motion with non-zero acceleration to scale", "all-zero record")
        factor = target * G0 / self.pga
        return self._derived(
            self.time_step, self.accel * factor, f"scaled to PGA {target:.6g} g (x{factor:.6g})"
        )

    def time_scaled(self, factor: float) -> GroundMotion:
        """Compress time by ``factor``: t' = t / factor, the same acceleration samples.

        ``factor = 2`` is the report's time scaling (Section 8.2).  The sample
        interval becomes ``time_step / factor``; velocities are divided by
        ``factor`` and displacements by ``factor**2``; frequencies are
        multiplied by ``factor``.  ``factor < 1`` stretches time.

        Parameters
        ----------
        factor : float
            Time-compression factor (dimensionless, positive).
        """
        number = _positive("time scale", factor)
        return self._derived(
            self.time_step / number, self.accel, f"time compressed by {number:.6g} (t' = t/{number:.6g})"
        )

    def resampled(self, time_step: float) -> GroundMotion:
        """Anti-aliased resampling to a new sample interval [s].

        Uses :func:`scipy.signal.resample_poly` (polyphase FIR, Kaiser window
        with beta = 5) with the rational ratio ``up/down = old_dt/new_dt``;
        the ratio must be a fraction with terms <= :data:`MAX_RESAMPLE_FACTOR`
        to a relative 1e-9 (0.01 s -> 0.0005 s is 20/1, 0.02 s -> 0.0005 s is
        40/1).  Samples outside the record are taken as zero, so a record that
        does not start and end near zero rings slightly at its ends.  Downsampling
        removes content above the new Nyquist frequency.

        Raises
        ------
        ConfigError
            Non-positive interval, a ratio that is not such a fraction, or a
            resampled record longer than :data:`~impedance_mil.bounds.MAX_RECORD_SAMPLES`.
        """
        new_dt = _positive("time_step", time_step)
        ratio = self.time_step / new_dt
        frac = Fraction(ratio).limit_denominator(MAX_RESAMPLE_FACTOR)
        if frac.numerator > MAX_RESAMPLE_FACTOR or abs(float(frac) - ratio) > RESAMPLE_RATIO_RTOL * ratio:
            raise ConfigError(
                "time_step",
                f"a ratio old/new = {ratio:.9g} that is a fraction p/q with p, q <= {MAX_RESAMPLE_FACTOR}",
                time_step,
            )
        up, down = frac.numerator, frac.denominator
        check_count("time_step", self.npts * up / down, MAX_RECORD_SAMPLES, "samples in the resampled record")
        if up == down:
            return self._derived(self.time_step, self.accel, "resampled (unchanged)")
        out = scipy_signal.resample_poly(self.accel, up, down)
        return self._derived(
            self.time_step * down / up, out, f"resampled to dt = {new_dt:.6g} s ({up}/{down}, anti-aliased)"
        )

    def baseline_corrected(self, order: int = 3) -> GroundMotion:
        """Remove drift so the motion ends at rest where it started.

        A polynomial correction ``a_c(t) = sum_j c_j (t/T)**j`` (j = 0..order)
        is added to the acceleration.  Its coefficients make the final velocity
        and the final displacement exactly zero (integrated as in
        :meth:`displacement`) and, among all such polynomials, minimise the
        mean square of the corrected displacement: an equality-constrained
        least-squares problem, solved through its KKT system.  With
        ``order = 1`` the two end conditions fix the (linear) correction alone.
        This is the shake-table counterpart of Boore-type polynomial baseline
        fits: a motion that fits the stroke at both ends with the smallest
        drift the polynomial can remove.

        Parameters
        ----------
        order : int
            Degree of the correction polynomial, 1 to 6.
        """
        if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not 1 <= order <= 6:
            raise ConfigError("order", "an integer from 1 to 6", order)
        dt = self.time_step
        tau = np.linspace(0.0, 1.0, self.npts)
        basis = np.stack([tau**j for j in range(order + 1)])  # (m, n) accelerations
        vb, db = zip(*(integrate_piecewise_linear(b, dt) for b in basis))
        vb, db = np.array(vb), np.array(db)
        v0, d0 = integrate_piecewise_linear(self.accel, dt)
        m = order + 1
        # Scale the displacement basis to keep the KKT system well conditioned.
        scale = np.max(np.abs(db), axis=1)
        dbs = db / scale[:, None]
        constraints = np.stack([vb[:, -1] / scale, dbs[:, -1]])  # (2, m)
        rhs_c = -np.array([v0[-1], d0[-1]])
        kkt = np.zeros((m + 2, m + 2))
        kkt[:m, :m] = dbs @ dbs.T
        kkt[:m, m:] = constraints.T
        kkt[m:, :m] = constraints
        rhs = np.concatenate((-(dbs @ d0), rhs_c))
        coef = np.linalg.lstsq(kkt, rhs, rcond=None)[0][:m] / scale
        corrected = self.accel + coef @ basis
        return self._derived(dt, corrected, f"baseline-corrected (order-{order} polynomial)")

    def trimmed(self, start: float = 0.0, end: float | None = None) -> GroundMotion:
        """The part of the motion between ``start`` and ``end`` [s] (inclusive samples)."""
        first = int(round(float(start) / self.time_step))
        last = self.npts - 1 if end is None else int(round(float(end) / self.time_step))
        if not 0 <= first < last <= self.npts - 1:
            raise ConfigError("trim", f"0 <= start < end <= {self.duration:.6g} s", (start, end))
        return self._derived(
            self.time_step,
            self.accel[first : last + 1],
            f"trimmed to [{first * self.time_step:.6g}, {last * self.time_step:.6g}] s",
        )
