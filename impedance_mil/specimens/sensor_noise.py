"""Coloured sensor noise: a measured-like spectrum instead of white noise (issue 17).

A channel's noise has a total rms ``noise_rms_v`` [V] (the rms over 0 ... the
Nyquist frequency of the controller's loop, i.e. the rms of the noise as the
loop samples it) and, optionally, a :class:`NoiseSpectrum` that shapes it:

* ``white``: flat one-sided PSD ``S(f) = S0``;
* ``pink``: white plus 1/f with a corner frequency ``f_c`` [Hz],
  ``S(f) = S0 (1 + f_c / f)``: -1 slope in log-log well below ``f_c``, flat
  well above;
* ``table``: a PSD table (frequency [Hz], PSD [V^2/Hz]), interpolated
  linearly in log f - log S, held at its end values outside the table;

plus mains hum lines (a fundamental, 50 or 60 Hz, and its harmonics), each
with its own rms [V].  The broadband part carries the rest of the total:
``rms_broadband^2 = noise_rms_v^2 - sum(hum_rms_v^2)``.

:func:`unit_noise_block` synthesizes one period of the noise, in units of
``noise_rms_v`` (so that the sensing kernel's ``noise_rms * draw`` is
unchanged), in the frequency domain on the DFT grid of
:data:`NOISE_PERIOD_LOOPS` loops: each bin has the amplitude of the
requested PSD and a seeded random phase (a random-phase multisine, as
shaker controllers synthesize random vibration).  Its periodogram over the
period is the requested PSD in every bin, without the chi-square scatter of
shaped white noise, and its rms is the stated one; its values are Gaussian
by the central limit theorem (tens of thousands of bins), but the amplitude
of a bin does not fluctuate from one realization to the next as a recorded
noise's would.  The block is
circular: a run longer than the period repeats it without a seam.  The mean
(DC bin) is zero; a hum line sits on the DFT bin nearest its frequency
(within half a bin, 1 / (2 P T): 0.004 Hz at a 1 ms loop) with a seeded
random phase, and the broadband noise is removed from that bin, so the
lines and the broadband part are orthogonal over the period and the
block's rms is exactly 1 over it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError

#: Spectrum kinds a channel's noise may have.
SPECTRUM_KINDS = ("white", "pink", "table")

#: Period of the synthesized noise [loops]: 2**17 (131 s at a 1 ms loop, a DFT bin of 0.0076 Hz).
NOISE_PERIOD_LOOPS = 2**17


@dataclass(frozen=True)
class NoiseSpectrum:
    """Shape of a channel's noise (module docstring); the total rms is the sensor's ``noise_rms_v``.

    Parameters
    ----------
    kind : str
        One of :data:`SPECTRUM_KINDS`.
    corner_hz : float, optional
        1/f corner frequency [Hz] of ``pink`` (required there, positive).
    frequencies_hz : tuple of float
        PSD table frequencies [Hz] of ``table``, strictly increasing, positive.
    psd : tuple of float
        PSD table values [V^2/Hz] of ``table`` (one-sided), positive.
    hum_hz : tuple of float
        Frequencies [Hz] of the hum lines (fundamental and harmonics), positive.
    hum_rms_v : tuple of float
        rms [V] of each hum line, >= 0, one per ``hum_hz``.
    source : str
        Where the table came from (a file name), for display.
    """

    kind: str
    corner_hz: float | None = None
    frequencies_hz: tuple[float, ...] = ()
    psd: tuple[float, ...] = ()
    hum_hz: tuple[float, ...] = ()
    hum_rms_v: tuple[float, ...] = ()
    source: str = field(default="", compare=False)

    def __post_init__(self):
        if self.kind not in SPECTRUM_KINDS:
            raise ConfigError("noise_spectrum.kind", " or ".join(SPECTRUM_KINDS), self.kind)
        if self.kind == "pink":
            if self.corner_hz is None or not (math.isfinite(self.corner_hz) and self.corner_hz > 0):
                raise ConfigError(
                    "noise_spectrum.corner", "a positive 1/f corner frequency [Hz]", self.corner_hz
                )
        elif self.corner_hz is not None:
            raise ConfigError("noise_spectrum.corner", "no corner except with kind = 'pink'", self.corner_hz)
        f, s = np.asarray(self.frequencies_hz, float), np.asarray(self.psd, float)
        if self.kind == "table":
            if f.size < 2 or f.size != s.size:
                raise ConfigError(
                    "noise_spectrum.file", "at least two rows of frequency [Hz] and PSD", f.size
                )
            if not (np.all(np.isfinite(f)) and np.all(f > 0) and np.all(np.diff(f) > 0)):
                raise ConfigError("noise_spectrum.file", "positive, strictly increasing frequencies [Hz]")
            if not (np.all(np.isfinite(s)) and np.all(s > 0)):
                raise ConfigError("noise_spectrum.file", "positive finite PSD values (interpolated log-log)")
        elif f.size or s.size:
            raise ConfigError("noise_spectrum.file", "no PSD table except with kind = 'table'")
        if len(self.hum_hz) != len(self.hum_rms_v):
            raise ConfigError("noise_spectrum.hum_rms", "one rms per hum line", self.hum_rms_v)
        for h, a in zip(self.hum_hz, self.hum_rms_v):
            if not (math.isfinite(h) and h > 0):
                raise ConfigError("noise_spectrum.hum", "positive hum frequencies [Hz]", h)
            if not (math.isfinite(a) and a >= 0):
                raise ConfigError("noise_spectrum.hum_rms", "hum rms values >= 0", a)

    @property
    def hum_power(self) -> float:
        """Sum of the squared hum rms values [V^2]."""
        return float(sum(a * a for a in self.hum_rms_v))

    def shape(self, f_hz) -> np.ndarray:
        """Broadband one-sided PSD shape at ``f_hz`` [Hz] (relative; 0 at f = 0; the table's own [V^2/Hz])."""
        f = np.asarray(f_hz, dtype=float)
        out = np.zeros_like(f)
        pos = f > 0
        if self.kind == "white":
            out[pos] = 1.0
        elif self.kind == "pink":
            out[pos] = 1.0 + float(self.corner_hz) / f[pos]  # type: ignore[arg-type]
        else:
            lf = np.log(np.asarray(self.frequencies_hz, float))
            ls = np.log(np.asarray(self.psd, float))
            # np.interp holds the end values outside the table
            out[pos] = np.exp(np.interp(np.log(f[pos]), lf, ls))
        return out

    def table_power(self, loop_time_s: float) -> float:
        """Integral [V^2] of the table's PSD over 0 ... the Nyquist frequency, on the noise's DFT grid."""
        f = dft_frequencies(loop_time_s)
        return float(np.sum(self.shape(f)[1:]) / (NOISE_PERIOD_LOOPS * loop_time_s))

    def check_hum(self, loop_time_s: float, where: str = "noise_spectrum") -> None:
        """Refuse hum lines at or above the Nyquist frequency of a ``loop_time_s`` [s] loop."""
        nyquist = 0.5 / loop_time_s
        for h in self.hum_hz:
            if h >= nyquist:
                raise ConfigError(
                    f"{where}.hum", f"hum lines below the loop's Nyquist frequency ({nyquist:g} Hz)", h
                )


def dft_frequencies(loop_time_s: float) -> np.ndarray:
    """Frequencies [Hz] of the one-sided DFT bins of one noise period (:data:`NOISE_PERIOD_LOOPS` loops)."""
    return np.fft.rfftfreq(NOISE_PERIOD_LOOPS, loop_time_s)


def unit_noise_block(
    spectrum: NoiseSpectrum, noise_rms_v: float, loop_time_s: float, rng: np.random.Generator
) -> np.ndarray:
    """One period of a channel's noise in units of ``noise_rms_v``: rms exactly 1 over the period.

    Parameters
    ----------
    spectrum : NoiseSpectrum
        The noise's shape and hum lines.
    noise_rms_v : float
        Total rms [V] (> 0) the block will be scaled by; sets the hum lines' share.
    loop_time_s : float
        Sampling period of the noise, the controller's loop time [s].
    rng : numpy.random.Generator
        Source of the Gaussian spectrum and the hum phases.

    Returns
    -------
    ndarray, (NOISE_PERIOD_LOOPS,)
        float64 samples, one per loop.
    """
    n = NOISE_PERIOD_LOOPS
    spectrum.check_hum(loop_time_s)
    if not noise_rms_v > 0:
        return np.zeros(n)  # a silent channel: the kernel multiplies the draws by 0
    hum_share = spectrum.hum_power / noise_rms_v**2
    if hum_share > 1.0 + 1e-12:
        raise ConfigError(
            "noise_spectrum.hum_rms", f"hum lines whose total rms is within the noise ({noise_rms_v:g} V)"
        )
    f = dft_frequencies(loop_time_s)
    amplitude = np.sqrt(spectrum.shape(f))
    bins = [int(round(h * n * loop_time_s)) for h in spectrum.hum_hz]
    amplitude[bins] = 0.0  # the lines own their bins (orthogonal to the broadband part)
    phases = rng.uniform(0.0, 2.0 * math.pi, f.size)
    spectrum_bins = amplitude * np.exp(1j * phases)
    spectrum_bins[-1] = amplitude[-1] * np.sign(
        np.cos(phases[-1])
    )  # the Nyquist bin of an even period is real
    broadband = np.fft.irfft(spectrum_bins, n)
    power = float(np.mean(broadband**2))
    block = np.zeros(n)
    if power > 0:
        block += broadband * math.sqrt(max(1.0 - hum_share, 0.0) / power)
    t = np.arange(n)
    phases = rng.uniform(0.0, 2.0 * math.pi, len(bins))
    for k, a, phase in zip(bins, spectrum.hum_rms_v, phases):
        block += math.sqrt(2.0) * (a / noise_rms_v) * np.cos(2.0 * math.pi * k * t / n + phase)
    return block
