"""The high-frequency instability interlock: its criterion, defaults and sources (no numba here).

A real table is stopped when its control loop goes unstable, before the
motion grows to the stroke or the velocity limit.  The criterion of the
virtual lab's ``hf_oscillation`` trip (:attr:`~impedance_mil.lab.trips.TripCause.HF_OSCILLATION`):

    the measured table acceleration, high-passed above ``hf_cutoff``, has an
    rms over consecutive windows of ``hf_window`` that grows by more than the
    factor ``hf_growth`` from one window to the next ``hf_windows`` times in
    a row, starting from a window whose rms is at least ``hf_floor``.

What each part rests on:

* **A growing oscillation is the definition of instability.**  A servo loop
  is unstable when a disturbance causes "oscillations with an amplitude that
  does not change or one that is quickly increasing" (Aerotech, *Automation1
  help, Glossary: Stability*, https://help.aerotech.com/automation1/Content/Glossary-Topics/Glossary-Stability.htm).
  An online indicator that watches the *growth* of the test's response, not
  its level, is what the real-time hybrid simulation literature uses to stop
  an unstable test before it damages the specimen or the equipment (Gálmez
  and Fermandois 2020, "Online stability analysis for real-time hybrid
  simulation testing", *Frontiers in Built Environment* 6:134,
  doi:10.3389/fbuil.2020.00134: an energy-based indicator computed during the
  test).  The level alone cannot be the criterion: the report's stable runs
  at 0.8-0.9 m_st carry large 15+ Hz oscillations (Figure 9.33), the unstable
  one at 0.7 m_st grows (Figure 9.34).
* **The band, 15 Hz and up** (:data:`HF_CUTOFF_HZ`): the report's unstable
  MIL runs oscillate "at 15+ Hz" (Section 9.4.4, Figures 9.33-9.34), below
  10 Hz the MIL performance is unaffected; the tracking instability of
  footnote 22 (f_c > 100 Hz) is a "highly oscillatory table response".  The
  oil-column poles that the report's root loci (Figure 4.7: 26-27 Hz) show
  crossing the imaginary axis for K_e > 6.7 V/in lie in this band.
  The campaign metric ``hf_ratio`` uses the same frequency
  (:data:`impedance_mil.campaign.runmetrics.HIGH_FREQUENCY_HZ`).
* **The window** (:data:`HF_WINDOW_S` = 0.2 s): three periods of the band's
  lowest frequency, so a window's rms of a 15 Hz oscillation is within a few
  per cent of its amplitude / sqrt 2 whatever the phase (tool's choice).
* **Growth factor and count** (:data:`HF_GROWTH` = 2, :data:`HF_WINDOWS` = 3):
  the amplitude doubling every window three windows running, an eightfold
  growth in 0.6 s, a growth rate of at least ln 2 / 0.2 s = 3.5 1/s (a mode of
  25 Hz with a damping ratio of -2.2 % or less).  A stationary response, how
  large it may be, does not double three times in a row (tool's choice; the
  margin of the report's stable runs is measured in ``docs/limits.md``).
  A loop that is unstable more slowly is left to the other interlocks (stroke,
  velocity, ``command_oscillation``, divergence).
* **The floor** (:data:`HF_FLOOR_NOISE_MULTIPLE` = 10 times the
  accelerometer's noise, :func:`default_floor`): the growth chain starts from
  a window at least an order of magnitude above what the sensor noise alone
  gives (the lab's default, 1 mV rms on the 0.6711 g/V accelerometer of
  Table 7.1: 0.26 in/s**2; a lab file's noisier accelerometer raises it), so
  noise, and a motion's first arrival out of the noise, are not growth.

The high-pass is a second-order Butterworth discretized by the bilinear
transform with the cutoff prewarped (:func:`highpass_coefficients`): two
poles, five multiplications a loop.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..errors import ConfigError
from ..specimens.sensors import REPORT_CHANNELS

#: Lower edge of the band of the instability [Hz] (report Section 9.4.4, Figures 9.33-9.34: 15+ Hz).
HF_CUTOFF_HZ = 15.0

#: Length of one rms window [s]: three periods of :data:`HF_CUTOFF_HZ`.
HF_WINDOW_S = 3.0 / HF_CUTOFF_HZ

#: Window-to-window rms ratio counted as growth [-] (the amplitude doubling).
HF_GROWTH = 2.0

#: Consecutive growing windows that trip [-].
HF_WINDOWS = 3

#: The floor in multiples of the default accelerometer noise [-].
HF_FLOOR_NOISE_MULTIPLE = 10.0

#: Default sensor noise of the virtual lab [V rms] (the value of
#: :data:`impedance_mil.lab.setup.DEFAULT_NOISE_V`, repeated here to keep this module's imports light).
_DEFAULT_NOISE_V = 1.0e-3


def default_floor(accel_noise: float | None = None) -> float:
    """The default ``hf_floor`` [in/s**2]: ten times the accelerometer's noise, at least the default's.

    ``accel_noise`` is the accelerometer channel's rms noise [in/s**2]
    (noise and quantization, :func:`impedance_mil.lab.setup.accelerometer_noise`);
    None: the lab's default, 1 mV rms on the Table 7.1 accelerometer (0.6711
    g/V), 0.2593 in/s**2.  A quieter (or noise-free) channel keeps the
    default's floor, 2.593 in/s**2 (0.0067 g): without it a noise-free model
    study would count the first 15+ Hz motion of a ground motion out of
    nothing as growth.
    """
    accel = next(s for s in REPORT_CHANNELS if s.quantity == "table_acceleration")
    default = _DEFAULT_NOISE_V * abs(accel.scale)
    noise = default if accel_noise is None else max(float(accel_noise), default)
    return HF_FLOOR_NOISE_MULTIPLE * noise


class HighPass(NamedTuple):
    """A second-order section ``y = b0 x + b1 x1 + b2 x2 - a1 y1 - a2 y2`` and the window in loops.

    ``window_loops`` is the number of loops of one rms window (at least 1).
    """

    b0: float
    b1: float
    b2: float
    a1: float
    a2: float
    window_loops: int


def highpass_coefficients(cutoff_hz: float, loop_time: float, window_s: float) -> HighPass:
    """Second-order Butterworth high-pass at ``cutoff_hz`` [Hz], sampled every ``loop_time`` [s].

    Bilinear transform with the cutoff prewarped (the -3 dB point is exactly
    ``cutoff_hz``): with ``K = tan(pi f_c T)`` and ``n = 1 + sqrt2 K + K^2``,
    ``b = (1, -2, 1) / n``, ``a1 = 2 (K^2 - 1) / n``, ``a2 = (1 - sqrt2 K + K^2) / n``.
    ``window_s`` [s] is rounded to a whole number of loops.

    Raises
    ------
    ConfigError
        ``cutoff_hz`` is not below the Nyquist frequency, or the window is shorter than a loop.
    """
    nyquist = 0.5 / loop_time
    if not (math.isfinite(cutoff_hz) and 0 < cutoff_hz < nyquist):
        raise ConfigError(
            "limits.hf_cutoff", f"a frequency in (0, {nyquist:g}) Hz (below Nyquist)", cutoff_hz
        )
    loops = round(window_s / loop_time)
    if loops < 1:
        raise ConfigError("limits.hf_window", f"at least one loop ({loop_time:g} s)", window_s)
    k = math.tan(math.pi * cutoff_hz * loop_time)
    r2 = math.sqrt(2.0)
    n = 1.0 + r2 * k + k * k
    return HighPass(1.0 / n, -2.0 / n, 1.0 / n, 2.0 * (k * k - 1.0) / n, (1.0 - r2 * k + k * k) / n, loops)


def growth_statistic(rms, windows: int, floor: float) -> float:
    """The detector's statistic over a run: how close its windows came to tripping [-].

    The largest, over every run of ``windows`` consecutive window-to-window
    ratios of ``rms`` (window rms [in/s**2], as
    :func:`impedance_mil.lab.kernels.hf_window_history` gives them) whose
    first window is at least ``floor`` [in/s**2], of the smallest ratio in
    the run.  The detector trips when this exceeds ``hf_growth``; on a run
    that did not trip, ``statistic / hf_growth`` is its margin (0 when no
    window reached the floor ``windows`` windows before the end).
    """
    best = 0.0
    for k in range(windows, len(rms)):
        if rms[k - windows] < floor:
            continue
        ratios = [rms[j] / rms[j - 1] for j in range(k - windows + 1, k + 1)]
        best = max(best, min(ratios))
    return float(best)


#: The detector switched off (never trips; the filter is not run).
HIGHPASS_OFF = HighPass(0.0, 0.0, 0.0, 0.0, 0.0, 0)


__all__ = [
    "HF_CUTOFF_HZ",
    "HF_FLOOR_NOISE_MULTIPLE",
    "HF_GROWTH",
    "HF_WINDOWS",
    "HF_WINDOW_S",
    "HIGHPASS_OFF",
    "HighPass",
    "default_floor",
    "growth_statistic",
    "highpass_coefficients",
]
