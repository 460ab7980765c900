"""Identifying a table from a recorded drive and response (``imil identify``).

:func:`identify_recording` takes a checked recording of the command ``u`` and a
response (``z``, ``x`` or ``dp``) and

1. estimates the FRF with its standard deviation and coherence: synchronous
   averaging over the periods of a multisine drive (its metadata gives the lines
   and periods, :mod:`impedance_mil.signals.drive`), or Welch's H1 for a random
   drive (:mod:`impedance_mil.signals.frf_estimators`);
2. fits the physical model (report Sections 4.3.5, 4.5: ``f_oil``, ``zeta_oil``,
   ``d`` and optionally the valve poles, for the chosen delay treatment:
   :func:`impedance_mil.lab.identification.identify_table`) and a rational
   transfer function of a chosen or automatically selected order
   (:mod:`impedance_mil.plant.rational`), both weighted by the inverse standard
   deviation of the estimate, with 95 % confidence intervals from the Jacobian;
3. states the fit error per band (:data:`IDENT_BANDS_HZ`), the coherence, and
   the identified values, and gives the text of a table file
   (:mod:`impedance_mil.plant.table_files`).

With two or more recordings of the same multisine whose article force ``w``
differs (the bare table and the table with a mass, or two masses), the command
path and the force path are separated line by line
(:func:`impedance_mil.signals.frf_two_input.two_input_frf`): the physical and
rational fits are made on the command path ``y/u`` (what one bare-table test
gives), and a rational model of the force path ``y/w`` is fitted as well, so
that the transfer-function table holds both ``H_zu`` and ``H_zw``: what a MIL
design needs (one test cannot separate them: with an article on the table ``w``
follows ``z``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..plant import TableParameters
from ..plant.capacity import TableCapacity
from ..plant.rational import RationalFit, fit_rational, select_order
from ..plant.table_files import physical_table_toml, transfer_function_toml
from ..signals.drive import DriveFile
from ..signals.frf import FRF
from ..signals.frf_estimators import synchronous_frf, welch_frf
from ..signals.frf_two_input import TwoInputFRF, two_input_frf
from ..signals.limits import TableLimits
from ..signals.recordings import Recording
from .identification import IDENTIFIABLE, TableIdentification, identify_table, model_response

#: Responses that can be identified against ``u``, with their zeros at the origin
#: (``z = s^2 x``; ``dp`` drives the mass: ``A_p dp = m_st s^2 x`` for the bare table).
OUTPUT_ZEROS = {"z": 2, "x": 0, "dp": 2}
#: The same for the force path ``y/w``: a position-controlled table yields to a
#: static force (``x/w`` finite at DC, so ``z/w`` has two zeros at the origin), and
#: the pressure carries it (``dp/w -> -1/A_p`` at DC).
FORCE_ZEROS = {"z": 2, "x": 0, "dp": 0}
#: Bands of the fit error [Hz].
IDENT_BANDS_HZ = ((0.25, 10.0), (10.0, 50.0), (50.0, 100.0))
#: Models an identification writes as a table file.
MODELS = ("physical", "tf")
#: Units of each signal in a transfer-function table file (internal units).
SIGNAL_UNITS = {"u": "in", "w": "lbf", "z": "in/s**2", "x": "in", "dp": "psi"}


def band_key(band: tuple[float, float]) -> str:
    """``fit_error_0p25_10hz`` for (0.25, 10)."""
    return "fit_error_" + "_".join(f"{v:g}".replace(".", "p") for v in band) + "hz"


def log_error(h_model, h_meas) -> float:
    """RMS ``|log(H_model / H_meas)|`` (real part and wrapped phase)."""
    r = np.log(np.asarray(h_model) / np.asarray(h_meas))
    return float(np.sqrt(np.mean(r.real**2 + np.angle(np.exp(1j * r.imag)) ** 2)))


def band_errors(frf: FRF, model: np.ndarray) -> dict[str, float | None]:
    """The fit error in each band of :data:`IDENT_BANDS_HZ` (None for a band without lines)."""
    out: dict[str, float | None] = {}
    for band in IDENT_BANDS_HZ:
        keep = (frf.frequency_hz >= band[0]) & (frf.frequency_hz <= band[1])
        out[band_key(band)] = log_error(model[keep], frf.response[keep]) if np.any(keep) else None
    return out


def recorded_frf(
    recording: Recording, output: str, drive: DriveFile | None = None, segment_points: int | None = None
) -> tuple[FRF, str]:
    """The FRF ``output/u`` of a recording and the estimator's name (synchronous with a multisine drive)."""
    if output not in OUTPUT_ZEROS:
        raise ConfigError("--output", "one of " + ", ".join(OUTPUT_ZEROS), output)
    missing = [c for c in ("u", output) if c not in recording.channels]
    if missing:
        raise ConfigError("--channel", f"the channels u and {output} (map {missing[0]}=COLUMN[UNIT])")
    u, y = recording.channels["u"], recording.channels[output]
    if drive is not None and drive.kind == "multisine":
        frf = synchronous_frf(
            u, y, drive.n_points, recording.sample_rate_hz, drive.lines, drive.discard_periods
        )
        return frf, f"synchronous average over {frf.n_averages} periods"
    if segment_points is None:
        raise ConfigError(
            "--segment", "a segment length in samples for a random drive (or --drive of a multisine)"
        )
    frf = welch_frf(u, y, recording.sample_rate_hz, int(segment_points))
    return frf, f"Welch H1, Hann window, {segment_points} samples, half overlap, {frf.n_averages} segments"


@dataclass(frozen=True, eq=False)
class RecordedIdentification:
    """The FRF of a recording and the physical and rational models fitted to it.

    Attributes
    ----------
    frf : FRF
        The estimate in the fitted band (with ``std``).
    estimator : str
    output : str
    physical : TableIdentification
    rational : RationalFit
    recording : Recording
    drive : DriveFile or None
    force_frf : FRF or None
        The force path ``output/w`` in the fitted band, from several tests (None for one test).
    force_rational : RationalFit or None
        Its rational model (biproper for ``z``: ``z/w -> 1/m`` at high frequency).
    condition_max : float or None
        Largest condition number of the tests' inputs over the band (1 is best).
    recordings : tuple of Recording
        Every test (the first is ``recording``).
    """

    frf: FRF
    estimator: str
    output: str
    physical: TableIdentification
    rational: RationalFit
    recording: Recording
    drive: DriveFile | None
    force_frf: FRF | None = None
    force_rational: RationalFit | None = None
    condition_max: float | None = None
    recordings: tuple[Recording, ...] = ()

    @property
    def coherence_min(self) -> float:
        return float(np.min(self.frf.coherence))

    def physical_response(self) -> np.ndarray:
        return model_response(
            self.physical.parameters, self.output, self.frf.frequency_hz, self.physical.delay
        )

    def physical_summary(self) -> dict[str, Any]:
        """Identified values with 95 % intervals, the misfit per band, the delay model."""
        ident = self.physical
        values = {name: ident.fit.parameters[name] for name in ident.fit.free}
        return {
            "model": "physical",
            "delay": ident.delay,
            "parameters": values,
            "ci95": {k: list(v) for k, v in ident.intervals().items()},
            "fit_error": ident.rms_log_error,
            "chi2_reduced": ident.fit.chi2_reduced,
            **band_errors(self.frf, self.physical_response()),
        }

    def rational_summary(self) -> dict[str, Any]:
        """Poles, DC gain, intervals and the misfit per band of the rational model."""
        fit = self.rational
        return {
            "model": "tf",
            **fit.to_dict(),
            "fit_error": fit.rms_log_error,
            **band_errors(self.frf, fit.response(self.frf.frequency_hz)),
        }

    def force_summary(self) -> dict[str, Any] | None:
        """Poles, DC gain, intervals and misfit of the force path's rational model (None for one test)."""
        if self.force_frf is None or self.force_rational is None:
            return None
        fit = self.force_rational
        return {
            "path": f"{self.output}/w",
            **fit.to_dict(),
            "fit_error": fit.rms_log_error,
            "condition_max": self.condition_max,
            **band_errors(self.force_frf, fit.response(self.force_frf.frequency_hz)),
        }

    def summary(self, model: str) -> dict[str, Any]:
        """The chosen model's figures at the top level (``poles_hz``, ``dc_gain``, ``fit_error``
        ``coherence_min`` for ``tf``), both models under ``physical`` and ``tf``, the FRF and the recording."""
        if model not in MODELS:
            raise ConfigError("--model", "one of " + ", ".join(MODELS), model)
        physical, rational = self.physical_summary(), self.rational_summary()
        chosen = physical if model == "physical" else rational
        f = self.frf.frequency_hz
        return {
            **chosen,
            "output": self.output,
            "coherence_min": self.coherence_min,
            "physical": physical,
            "tf": rational,
            "frf": {
                "estimator": self.estimator,
                "n_lines": int(f.size),
                "f_min_hz": float(f.min()),
                "f_max_hz": float(f.max()),
                "coherence_min": self.coherence_min,
                "coherence_median": float(np.median(self.frf.coherence)),
            },
            "recording": self.recording.provenance(),
            "drive": None if self.drive is None else self.drive.to_dict(),
            **(
                {}
                if self.force_frf is None
                else {
                    "force_path": self.force_summary(),
                    "recordings": [rec.provenance() for rec in self.recordings],
                }
            ),
        }

    def table_text(self, model: str, source: str) -> str:
        """The table file of the chosen model, with a header saying where it came from."""
        header = [
            f"Identified by imil identify from {source} ({self.estimator}, {self.frf.frequency_hz.size} lines "
            f"{self.frf.frequency_hz.min():.4g}-{self.frf.frequency_hz.max():.4g} Hz, "
            f"coherence >= {self.coherence_min:.3f}).",
        ]
        if model == "physical":
            ident = self.physical
            for name, (lo, hi) in ident.intervals().items():
                header.append(
                    f"{name} = {ident.fit.parameters[name]:.6g} (95 % interval {lo:.6g} .. {hi:.6g})"
                )
            header.append(
                f"fit error (rms |log(H_model/H_meas)|) {ident.rms_log_error:.4f}; delay model {ident.delay}"
            )
            return physical_table_toml(ident.parameters, header)
        fit = self.rational
        header.append(
            f"order {fit.order}, numerator degree {fit.num_order} with {fit.zeros_at_origin} zeros at the origin; "
            f"poles {', '.join(f'{p:.4g}' for p in fit.poles_hz)} Hz; DC gain {fit.dc_gain:.6g}; "
            f"fit error {fit.rms_log_error:.4f}"
        )
        paths = {"u": fit}
        if self.force_rational is not None:
            force = self.force_rational
            header.append(
                f"force path {self.output}/w from {len(self.recordings)} tests: order {force.order}, poles "
                f"{', '.join(f'{p:.4g}' for p in force.poles_hz)} Hz; fit error {force.rms_log_error:.4f}"
            )
            paths["w"] = force
        units = {name: SIGNAL_UNITS[name] for name in (*paths, self.output)}
        return transfer_function_toml(
            paths,
            output=self.output,
            units=units,
            loop_time=self.recording.time_step,
            header=header,
            capacity=implied_capacity(self.physical.parameters),
        )


def implied_capacity(params: TableParameters) -> TableCapacity:
    """What the table file's physical parameters imply it can do: its mid-stroke, the valve's
    no-load velocity, the stall force ``A_p (P_S - P_R)``, the moving mass and the piston area
    (internal units; :meth:`impedance_mil.signals.limits.TableLimits.from_table`)."""
    limits = TableLimits.from_table(params)
    return TableCapacity(
        stroke=limits.stroke_in,
        velocity=limits.velocity_in_s,
        force=limits.force_lbf,
        mass=params.mass,
        piston_area=params.piston_area,
    )


def identify_recording(
    recording: Recording | Sequence[Recording],
    initial: TableParameters,
    *,
    output: str = "z",
    drive: DriveFile | None = None,
    segment_points: int | None = None,
    order: int | None = None,
    num_order: int | None = None,
    zeros_at_origin: int | None = None,
    delay: str = "first-order",
    free: Sequence[str] = ("f_oil_hz", "zeta_oil", "d"),
    f_range_hz: tuple[float, float] = (0.25, 100.0),
) -> RecordedIdentification:
    """Estimate the FRF of a recording and fit the physical and rational models (see the module docstring).

    Parameters
    ----------
    recording : Recording or sequence of Recording
        With ``u`` [in] and ``output``.  Several recordings of the same
        multisine, each with the article force ``w`` [lbf] as well, whose ``w``
        differ: the command and force paths are then separated
        (:func:`~impedance_mil.signals.frf_two_input.two_input_frf`).
    initial : TableParameters
        The table file's parameters: the starting values of the physical fit, and
        the known gains, loop time, area, mass and stroke.
    output : {"z", "x", "dp"}
    drive : DriveFile, optional
        The multisine that was played (lines, periods); without it, Welch with ``segment_points``.
    segment_points : int, optional
        Segment length of the Welch estimate [samples].
    order : int, optional
        Poles of the rational model; None: selected by BIC (:func:`select_order`).
    num_order : int, optional
        Numerator degree of the rational model (with ``order``).
    zeros_at_origin : int, optional
        Known zeros at s = 0 (default :data:`OUTPUT_ZEROS` of the output).
    delay : str
        Delay treatment of the physical model (``plant.linear.DELAYS``).
    free : sequence of str
        Parameters of the physical fit (:data:`~impedance_mil.lab.identification.IDENTIFIABLE`).
    f_range_hz : (float, float)
        Band of both fits [Hz].
    """
    unknown = [name for name in free if name not in IDENTIFIABLE]
    if unknown:
        raise ConfigError("--free", "names from " + ", ".join(IDENTIFIABLE), ",".join(unknown))
    recordings = (recording,) if isinstance(recording, Recording) else tuple(recording)
    two: TwoInputFRF | None = None
    if len(recordings) == 1:
        estimate, estimator = recorded_frf(recordings[0], output, drive, segment_points)
    else:
        two = force_path_frf(recordings, output, drive)
        estimate = two.command
        estimator = f"two-input synchronous average of {two.n_tests} tests over {estimate.n_averages} periods"
    frf = estimate.band(*f_range_hz)
    if frf.frequency_hz.size < 4:
        raise ConfigError("--band", "a band holding at least 4 measured lines", f_range_hz)
    weights = np.sqrt(2.0) * np.abs(frf.response) / frf.std
    physical = identify_table(
        frf, initial, output=output, free=free, delay=delay, f_range_hz=f_range_hz, weights=weights
    )
    q = OUTPUT_ZEROS[output] if zeros_at_origin is None else int(zeros_at_origin)
    if order is None:
        rational = select_order(frf, zeros_at_origin=q, weights=weights)
    else:
        rational = fit_rational(frf, order, num_order=num_order, zeros_at_origin=q, weights=weights)
    if two is None:
        return RecordedIdentification(
            frf, estimator, output, physical, rational, recordings[0], drive, recordings=recordings
        )
    force = two.force.band(*f_range_hz)
    keep = (two.command.frequency_hz >= f_range_hz[0]) & (two.command.frequency_hz <= f_range_hz[1])
    force_weights = np.sqrt(2.0) * np.abs(force.response) / force.std
    qw = FORCE_ZEROS[output]
    # The force path's order is the command path's (one table, one closed loop); for z it is
    # biproper (z/w -> 1/m_st at high frequency), so its numerator has the denominator's degree.
    force_fit = fit_rational(
        force, rational.order, num_order=rational.order - qw, zeros_at_origin=qw, weights=force_weights
    )
    return RecordedIdentification(
        frf,
        estimator,
        output,
        physical,
        rational,
        recordings[0],
        drive,
        force_frf=force,
        force_rational=force_fit,
        condition_max=float(np.max(two.condition[keep])),
        recordings=recordings,
    )


def force_path_frf(recordings: Sequence[Recording], output: str, drive: DriveFile | None) -> TwoInputFRF:
    """The command and force paths of ``output`` from several recordings of one multisine.

    Raises
    ------
    ConfigError
        No multisine drive (``--drive``), a recording without ``u``, ``w`` or
        ``output`` (naming the channel), or tests that do not separate the paths.
    """
    if output not in FORCE_ZEROS:
        raise ConfigError("--response", "one of " + ", ".join(FORCE_ZEROS), output)
    if drive is None or drive.kind != "multisine":
        raise ConfigError(
            "--drive", "the multisine played in every test (several recordings are averaged by period)"
        )
    tests = []
    for rec in recordings:
        missing = [c for c in ("u", "w", output) if c not in rec.channels]
        if missing:
            raise ConfigError(
                "--channel",
                f"the channels u, w and {output} in every recording (map {missing[0]}=COLUMN[UNIT]; "
                f"missing in {rec.path.name})",
            )
        tests.append((rec.channels["u"], rec.channels["w"], rec.channels[output]))
    return two_input_frf(
        tests, drive.n_points, recordings[0].sample_rate_hz, drive.lines, drive.discard_periods
    )
