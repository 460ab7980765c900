"""Virtual experiments of the report: frequency response (4.5), tracking (8), MIL (9).

Each function builds the nonlinear virtual table from the linear model's
parameters (:meth:`NonlinearTable.from_linear`, unless a table is given: a
physical one or an LTI table, :func:`~impedance_mil.lab.lti_plant.virtual_table_for`),
runs the compiled loop and returns a named result; the CLI and the HTML
report call these.

* :func:`run_frf`: multisine command (Section 4.5.2) through the table (bare
  or with a specimen), H1 FRFs of ``z``, ``x``, ``dP`` (and ``w``), the linear
  model's prediction (Eq 4-15; with a specimen, ``H_zu + H_zw W/U`` from the
  measured force, Section 4.5.4) and the identified parameters.  A run
  stopped by a safety limit is returned with ``run.trip`` set and no FRF.
* :func:`kp_study`: :func:`run_frf` over K_p values and the misfit of the
  identified linear model at each (Sections 4.5.3.1, 8.3.3).
* :func:`run_tracking`: ``z_vs = a_g`` with the tracking controller (Eq 1-6).
* :func:`run_mil`: a virtual isolation system with the standardized controller.

An argument left as ``None`` takes the report's value from the report's setup
file (:func:`impedance_mil.report_config.report_config`: f_c, feedback,
precision, plant substeps, multisine peak, delay model, K_p values); no value
is written in a signature here.  :mod:`impedance_mil.lab.descriptions` builds
complete, named descriptions of the same experiments (what the CLI and the
campaigns run).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..design import ControllerDesign, design_controller, table_model, virtual_model
from ..errors import ConfigError
from ..implement import MILRuntime
from ..implement.export import controller_from_design
from ..plant import TableParameters
from ..plant.lti_table import LTITable
from ..plant.nonlinear import NonlinearTable
from ..report_config import report_config
from ..signals import GroundMotion
from ..signals.frf import estimate_frf
from ..signals.multisine import Multisine, design_multisine
from .chunks import RecordSink
from .feedback import Feedback
from .identification import TableIdentification, identify_table, model_response
from .loop import simulate
from .lti_plant import LTIVirtualTable, virtual_table_for
from .metrics import RunMetrics, evaluate_run, vs_force_history
from .results import RunResult
from .setup import SafetyLimits

#: Measured channels whose FRF against u is estimated, by model output name.
FRF_CHANNELS = {"z": "z_meas", "x": "x_meas", "dp": "dp_meas"}


@dataclass(frozen=True, eq=False)
class FrfExperiment:
    """Outcome of :func:`run_frf`.

    Attributes
    ----------
    run : RunResult
        The multisine run (``run.trip`` is set when a safety limit stopped it;
        the data up to the trip are kept).
    multisine : Multisine
        The command.
    frf : dict of str to FRF
        Measured ``z/u`` [in/s^2/in], ``x/u`` [-], ``dp/u`` [psi/in] (and ``w/u``
        [lbf/in]); empty when the run tripped.
    model : dict of str to ndarray
        Linear-model prediction at the same lines (complex); empty when the run tripped.
    identification : TableIdentification or None
        Parameters identified from ``z/u`` (bare table only; None when the run tripped).
    params : TableParameters
        Linear-model parameters the virtual table was built from.
    delay : str
        Delay treatment of the linear model compared.
    """

    run: RunResult
    multisine: Multisine
    frf: dict
    model: dict
    identification: TableIdentification | None
    params: TableParameters | LTITable
    delay: str

    @property
    def completed(self) -> bool:
        """True when no safety limit stopped the run (the FRFs exist)."""
        return self.run.completed

    def model_error(self, output: str = "z", band_hz=(0.25, 100.0)) -> float:
        """RMS ``|log(H_model/H_meas)|`` over a band [Hz] (0.01 ~ 1 % / 0.6 deg).

        Raises
        ------
        LimitTripped
            The run tripped, so there is no measured FRF.
        """
        self.run.raise_if_tripped()
        f = self.frf[output].frequency_hz
        keep = (f >= band_hz[0]) & (f <= band_hz[1])
        r = np.log(self.model[output][keep] / self.frf[output].response[keep])
        return float(np.sqrt(np.mean(r.real**2 + np.angle(np.exp(1j * r.imag)) ** 2)))


@dataclass(frozen=True, eq=False)
class KpStudy:
    """Identification misfit of the linear model for several K_p [V/psi]."""

    kp: tuple
    experiments: tuple

    @property
    def misfit(self) -> np.ndarray:
        """``rms_log_error`` of the identified model at each K_p (NaN where the run tripped)."""
        return np.array(
            [np.nan if e.identification is None else e.identification.rms_log_error for e in self.experiments]
        )


@dataclass(frozen=True, eq=False)
class ControlledRun:
    """Outcome of :func:`run_tracking` or :func:`run_mil`.

    Attributes
    ----------
    run : RunResult
        All channels (``z_vs`` is the target).
    metrics : RunMetrics or None
        Errors against the target (None if the run tripped before 1 s).
    design : ControllerDesign
        The controller designed for the run.
    motion : GroundMotion
        The input motion at the loop rate.
    vs_force : ndarray or None
        The VS model's isolator force [lbf] along the run's VS states (a MIL run; None for
        tracking): computed once for the energy error and the model loop of the run file.
    """

    run: RunResult
    metrics: RunMetrics | None
    design: ControllerDesign
    motion: GroundMotion
    extra: dict = field(default_factory=dict)
    vs_force: np.ndarray | None = None


def _table(params, table, kp):
    """The virtual table of an experiment: ``table`` (a physical or LTI table), else that of ``params``.

    ``params``: physical parameters (``NonlinearTable.from_linear``), or a table
    given as a linear model (an :class:`~impedance_mil.plant.lti_table.LTITable`, run as it is).
    """
    if table is None:
        table = params if isinstance(params, LTITable) else NonlinearTable.from_linear(params)
    table = virtual_table_for(table)
    if kp is None:
        return table
    if isinstance(table, LTIVirtualTable):
        raise ConfigError(
            "kp", "no K_p override for an LTI table (its hydraulic loop is inside its model)", kp
        )
    return table.with_gains(Kp=kp)


def _model_responses(p, table, f, delay, channels) -> tuple[dict, dict]:
    """``(u responses, w responses)`` of the compared linear model at ``f`` [Hz] for ``channels``.

    For an LTI table its own model (the table is the model); otherwise the
    model of the parameters ``p`` with the delay treatment ``delay`` (Eq 4-15).
    """
    if isinstance(table, LTIVirtualTable):
        model = table.model
        return (
            {name: model.frequency_response(name, "u", f) for name in channels},
            {name: model.frequency_response(name, "w", f) for name in channels},
        )
    return (
        {name: model_response(p, name, f, delay) for name in channels},
        {name: model_response(p, name, f, delay, input="w") for name in channels},
    )


def run_frf(
    params: TableParameters | LTITable,
    *,
    multisine: Multisine | None = None,
    specimen=None,
    table=None,
    kp: float | None = None,
    delay: str | None = None,
    identify: bool = True,
    free=("f_oil_hz", "zeta_oil", "d"),
    f_range_hz=(0.25, 100.0),
    sensors=None,
    seed: int = 0,
    substeps: int | str | None = None,
    limits=None,
    quantize: bool = True,
    output_delay: int = 1,
) -> FrfExperiment:
    """Frequency-response experiment of Section 4.5 on the virtual table.

    Parameters
    ----------
    params : TableParameters
        Linear-model parameters (the virtual table is derived from them).
    multisine : Multisine, optional
        Command; default the report's (512 lines, 0.25-125 Hz, 3 x 8192
        points at the loop rate) with the report's peak (0.1 in, ``[frf] peak``).
    specimen : object, optional
        Test article (Section 4.5.4); ``None`` for the bare table (4.5.3).
    table : NonlinearTable or LTI table, optional
        Use this virtual table instead of ``from_linear(params)``: a physical
        table, or a linear table model (:func:`~impedance_mil.lab.lti_plant.virtual_table_for`),
        whose own model is then the compared one (``delay`` is unused) and
        whose FRFs are those of the outputs it has.
    kp : float, optional
        Override K_p [V/psi] of the virtual table (and of the model).
    delay : str, optional
        Delay treatment of the compared linear model (default the report's, first-order).
    identify : bool
        Fit ``free`` parameters to the measured ``z/u`` (bare table only).
    f_range_hz : (float, float)
        Band of the identification [Hz].
    sensors, seed, substeps, limits, quantize, output_delay
        As :func:`impedance_mil.lab.loop.simulate` (``substeps`` None: the report's policy).

    Returns
    -------
    FrfExperiment
        When a safety limit stops the run, ``run.trip`` says which and when,
        and there are no FRFs, model prediction or identification (empty
        dicts, None).
    """
    cfg = report_config()
    delay = cfg.frf.delay if delay is None else delay
    if identify and specimen is None and isinstance(params, LTITable):
        raise ConfigError(
            "identify",
            "no identification of omega_oil, zeta_oil and d for an LTI table (it has no physical "
            "parameters; fit a model to a recording with imil identify)",
        )
    vt = _table(params, table, kp)
    p = (
        params if kp is None or isinstance(params, LTITable) else params.replace(Kp=kp)
    )  # _table refused kp for LTI
    ms = multisine or design_multisine(peak=cfg.frf.peak_in, sample_rate_hz=1.0 / vt.loop_time)
    if not np.isclose(ms.sample_rate_hz * vt.loop_time, 1.0):
        raise ConfigError(
            "multisine.sample_rate_hz", f"the loop rate {1 / vt.loop_time:g} Hz", ms.sample_rate_hz
        )
    # No hf_oscillation detector in a multisine test: its low-crest phases sweep the lines in
    # time like a chirp, so the acceleration above 15 Hz grows within each period by design
    # (it tripped the report's K_p = 0.0002 test at 9.0 s); the other interlocks stay.
    frf_limits = dataclasses.replace(limits or SafetyLimits(), hf_cutoff=None)
    run = simulate(
        vt,
        command=ms.signal,
        specimen=specimen,
        sensors=sensors,
        seed=seed,
        substeps=cfg.controller.substeps if substeps is None else substeps,
        limits=frf_limits,
        quantize=quantize,
        output_delay=output_delay,
        config={"experiment": "frf"},
    )
    if run.trip is not None:
        return FrfExperiment(run, ms, {}, {}, None, p, delay)
    channels = {
        name: ch
        for name, ch in FRF_CHANNELS.items()
        if not (isinstance(vt, LTIVirtualTable) and name not in vt.outputs)
    }
    est = {
        name: estimate_frf(run.u, run.channels[ch], ms.n_points, ms.sample_rate_hz, lines=ms.lines)
        for name, ch in channels.items()
    }
    f = est["z"].frequency_hz
    model, model_w = _model_responses(p, vt, f, delay, channels)
    if specimen is not None:
        est["w"] = estimate_frf(run.u, run.w_lc, ms.n_points, ms.sample_rate_hz, lines=ms.lines)
        ratio = est["w"].response
        for name in channels:
            model[name] = model[name] + model_w[name] * ratio
    ident = (
        identify_table(est["z"], p, free=free, delay=delay, f_range_hz=f_range_hz)
        if identify and specimen is None and isinstance(p, TableParameters)  # LTI refused above
        else None
    )
    return FrfExperiment(run, ms, est, model, ident, p, delay)


def kp_study(params: TableParameters | LTITable, kp_values=None, **kwargs) -> KpStudy:
    """:func:`run_frf` with identification at each K_p [V/psi] (Sections 4.5.3.1, 8.3.3).

    ``kp_values`` None: the report's (``[frf] kp_values`` of the report's setup).
    """
    if kp_values is None:
        kp_values = report_config().frf.kp_values
    runs = tuple(run_frf(params, kp=kp, identify=True, **kwargs) for kp in kp_values)
    return KpStudy(tuple(kp_values), runs)


def _report_choices(fc_hz, feedback, precision) -> tuple[float, str, str]:
    """f_c [Hz], feedback channel and precision, the report's where None (``report_config``)."""
    cfg = report_config()
    return (
        cfg.design.fc_hz if fc_hz is None else fc_hz,
        Feedback.parse(cfg.controller.feedback).channel if feedback is None else feedback,
        cfg.controller.precision if precision is None else precision,
    )


def tracking_design(params: TableParameters | LTITable, fc_hz: float | None = None) -> ControllerDesign:
    """The tracking controller of :func:`run_tracking` (``z_vs = a_g``) at ``fc_hz`` [Hz] (default the report's)."""
    fc_hz = report_config().design.fc_hz if fc_hz is None else fc_hz
    return design_controller(table_model(params), form="tracking", fc_hz=fc_hz, emit_warnings=False)


def mil_design(params: TableParameters | LTITable, vs, fc_hz: float | None = None) -> ControllerDesign:
    """The standardized MIL controller of :func:`run_mil` for ``vs`` at ``fc_hz`` [Hz] (default the report's).

    Made with ``linearization="open-fh"``: its constraint verdicts are the
    conservative open-``f_h`` ones (see :func:`run_mil`).
    """
    fc_hz = report_config().design.fc_hz if fc_hz is None else fc_hz
    return design_controller(
        table_model(params),
        virtual_model(vs, linearization="open-fh"),
        form="standardized",
        fc_hz=fc_hz,
        emit_warnings=False,
    )


def _runtime(params, design, vs, precision, leak_hz):
    # export's discretization of the design, so that a run executes what `imil export` writes
    controller = controller_from_design(design, loop_time_s=params.loop_time, leak_hz=leak_hz)
    return MILRuntime(controller, vs=vs, precision=precision)


def _motion_info(gm) -> dict:
    return {
        "name": getattr(gm, "name", ""),
        "source": str(getattr(gm, "source", "")),
        "time_step_s": gm.time_step,
        "npts": gm.npts,
        "pga_g": gm.pga_g,
    }


def _controlled(
    params,
    motion,
    runtime,
    design,
    *,
    specimen,
    table,
    feedback,
    sensors,
    seed,
    substeps,
    limits,
    vs,
    name,
    output_delay=1,
    sink=None,
) -> ControlledRun:
    gm = motion.resampled(params.loop_time)
    vt = _table(params, table, None)
    if substeps is None:
        substeps = report_config().controller.substeps
    run = simulate(
        vt,
        a_g=gm.accel,
        runtime=runtime,
        specimen=specimen,
        feedback=feedback,
        sensors=sensors,
        seed=seed,
        substeps=substeps,
        limits=limits,
        output_delay=output_delay,
        sink=sink,
        config={
            "experiment": name,
            "motion": _motion_info(gm),
            "design": {"form": design.form, "fc_hz": design.fc_hz},
        },
    )
    vs_force = vs_force_history(vs, run.vs_states) if vs is not None and run.vs_states.size else None
    metrics = None
    if run.n_samples * params.loop_time >= 1.0:
        metrics = evaluate_run(run, vs=vs, ground_displacement=gm.displacement(), vs_force=vs_force)
    return ControlledRun(run, metrics, design, gm, vs_force=vs_force)


def run_tracking(
    params: TableParameters | LTITable,
    motion,
    *,
    specimen=None,
    fc_hz: float | None = None,
    feedback: str | None = None,
    compensate: bool = True,
    table=None,
    precision: str | None = None,
    leak_hz: float | None = None,
    sensors=None,
    seed: int = 0,
    substeps: int | str | None = None,
    limits=None,
    design: ControllerDesign | None = None,
    output_delay: int = 1,
    sink: RecordSink | None = None,
) -> ControlledRun:
    """Acceleration tracking, ``z_vs = a_g`` (Section 8, Eq 1-6).

    Parameters
    ----------
    params : TableParameters
        Table model used for the design and to derive the virtual table.
    motion : GroundMotion
        Input motion (resampled to the loop time) [in/s^2].
    specimen : object, optional
        Test article on the table.
    fc_hz : float, optional
        Filter cut-off [Hz] (default the report's, ``[design] fc``: 80 Hz).
    feedback : {"lc", "fe"}, optional
        Lab channel of w (Section 8.3.2; default the report's, ``[controller] feedback``).
    compensate : bool
        Include ``u_w`` (``False``: the third column of Figures 8.8-8.9).
    table, precision, leak_hz, sensors, seed, substeps, limits, output_delay, sink
        Virtual table override, controller arithmetic (default the report's,
        single), drift leak [Hz], and :func:`~impedance_mil.lab.loop.simulate`
        options (``substeps`` default the report's policy; ``output_delay`` in
        loops, default 1: the design's linear model assumes one loop; ``sink``
        receives the records as the run goes, e.g. the run file).
    design : ControllerDesign, optional
        The design to run (default :func:`tracking_design` at ``fc_hz``; a
        caller that checked its verdicts before the run passes it here).
    """
    fc_hz, feedback, precision = _report_choices(fc_hz, feedback, precision)
    if design is None:
        design = tracking_design(params, fc_hz)
    runtime = _runtime(params, design, None, precision, leak_hz)
    if not compensate:
        runtime.m_w[...] = 0
    return _controlled(
        params,
        motion,
        runtime,
        design,
        specimen=specimen,
        table=table,
        feedback=feedback,
        sensors=sensors,
        seed=seed,
        substeps=substeps,
        limits=limits,
        vs=None,
        name="tracking",
        output_delay=output_delay,
        sink=sink,
    )


def run_mil(
    params: TableParameters | LTITable,
    vs,
    motion,
    *,
    specimen=None,
    fc_hz: float | None = None,
    feedback: str | None = None,
    table=None,
    precision: str | None = None,
    leak_hz: float | None = None,
    sensors=None,
    seed: int = 0,
    substeps: int | str | None = None,
    limits=None,
    design: ControllerDesign | None = None,
    output_delay: int = 1,
    sink: RecordSink | None = None,
) -> ControlledRun:
    """MIL run imitating the virtual system ``vs`` (Section 9; standardized controller).

    Parameters are those of :func:`run_tracking`, plus ``vs``, a built-in
    :class:`~impedance_mil.virtual.base.VirtualSystem` (``presets.get("SD2")``).

    Notes
    -----
    The standardized controller (``H_uz``, ``H_uw``) does not depend on the
    equivalent linearization of an LR or FP isolator, which only changes the
    constraint evaluation; the design is therefore made with
    ``linearization="open-fh"`` (saves 0.3-1 s per run), and the returned
    ``design`` reports the conservative open-``f_h`` constraint verdicts.  Use
    :func:`~impedance_mil.design.design_controller` for the linearized verdicts.
    """
    fc_hz, feedback, precision = _report_choices(fc_hz, feedback, precision)
    if design is None:
        design = mil_design(params, vs, fc_hz)
    runtime = _runtime(params, design, vs, precision, leak_hz)
    return _controlled(
        params,
        motion,
        runtime,
        design,
        specimen=specimen,
        table=table,
        feedback=feedback,
        sensors=sensors,
        seed=seed,
        substeps=substeps,
        limits=limits,
        vs=vs,
        name="mil",
        output_delay=output_delay,
        sink=sink,
    )
