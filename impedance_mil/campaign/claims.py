"""The report's claims as data, each with an evaluation over campaign summary tables.

A :class:`Claim` quotes a statement of the report (with its section), names
the study of the built-in campaigns that tests it, and evaluates it on the
summary rows of that study: :func:`evaluate_claims` returns one
:class:`ClaimOutcome` per claim, with a verdict (``agree``, ``disagree`` or
``not run``), the toolkit's numbers in one sentence, and the curves of a
figure (plain numbers; :mod:`impedance_mil.report.reproduction` draws them).

The metrics compared are defined in :mod:`impedance_mil.campaign.runmetrics`
(spectral agreement of table and target) and in the kinds'
run functions (poles, constraints I-III).  Thresholds that turn the report's
visual judgements into numbers are named constants below.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import scipy.stats

from ..lab.feedback import LEGACY_NAMES, Feedback
from ..lab.runfile import legacy_value
from ..lab.trips import TRIP_LIMIT_KEY, TripCause
from .runmetrics import AGREEMENT_TOLERANCE
from .summary import SummaryTable

AGREE, DISAGREE, NOT_RUN = "agree", "disagree", "not run"

#: Relative margin by which one error must exceed another to count as "worse": the report
#: contrasts poor with accurate tracking, not differences at the noise level.
MEANINGFUL_RATIO = 1.25

#: Ratio of the table's rms acceleration above 15 Hz to the target's rms above which a MIL run
#: counts as unstable (high-frequency oscillation dominating the response, Figures 9.33-9.34).
HF_UNSTABLE = 1.0

#: Relative difference of oil-column damping between the first-order and the exact
#: sampled-data delay model below which the first-order model counts as accurate.
DELAY_MODEL_TOLERANCE = 0.15


@dataclass(frozen=True)
class Curve:
    """One line of a claim's figure.

    Attributes
    ----------
    label : str
        Legend entry.
    x, y : tuple of float
        Points.
    role : str
        ``"table"`` (the toolkit, solid blue), ``"target"`` (the report's value, dashed red)
        or ``"other"``.
    """

    label: str
    x: tuple[float, ...]
    y: tuple[float, ...]
    role: str = "table"


@dataclass(frozen=True)
class ClaimOutcome:
    """The verdict on one claim.

    Attributes
    ----------
    claim : Claim
    verdict : str
        ``"agree"``, ``"disagree"`` or ``"not run"``.
    measured : str
        The toolkit's numbers, one sentence.
    curves : tuple of Curve
        Data of the figure (empty when not run).
    xlabel, ylabel : str
        Axis labels with units.
    xlog : bool
        Logarithmic x axis.
    """

    claim: Claim
    verdict: str
    measured: str
    curves: tuple[Curve, ...] = ()
    xlabel: str = ""
    ylabel: str = ""
    xlog: bool = False


@dataclass(frozen=True)
class Claim:
    """A statement of the report and how the toolkit tests it.

    Attributes
    ----------
    id : str
        Short identifier (e.g. ``"sec9-band"``).
    section : str
        Report section (e.g. ``"9.3"``).
    statement : str
        The report's statement, quoted or closely paraphrased.
    campaign : str
        Built-in campaign that holds the study (``imil campaign run NAME``).
    study : str
        Study of that campaign whose rows the claim reads.
    test : str
        How the toolkit decides, one sentence.
    evaluate : callable
        ``evaluate(rows: SummaryTable) -> (verdict, measured, curves, xlabel, ylabel, xlog)``
        over the rows of ``study`` that finished.
    """

    id: str
    section: str
    statement: str
    campaign: str
    study: str
    test: str
    evaluate: Callable[[SummaryTable], tuple] = field(repr=False)


def _points(rows: SummaryTable, x: str, y: str, **where: Any) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Sorted (x, y) pairs of the rows matching ``where`` with numeric x and y."""
    pairs = []
    for row in rows.where(**where).rows:
        vx, vy = row.get(x), row.get(y)
        if isinstance(vx, (int, float)) and isinstance(vy, (int, float)):
            pairs.append((float(vx), float(vy)))
    pairs.sort()
    return tuple(p[0] for p in pairs), tuple(p[1] for p in pairs)


def _value(rows: SummaryTable, metric: str, **where: Any) -> float | None:
    values = rows.where(**where).values(metric)
    return values[0] if values else None


# ------------------------------------------------------------------ Section 4
def _kp_damping(rows: SummaryTable) -> tuple:
    x, y = _points(rows, "K_p", "oil_damping_ratio", delay="first-order")
    zero, best = _value(rows, "oil_damping_ratio", K_p=0.0), _value(rows, "oil_damping_ratio", K_p=0.001)
    if zero is None or best is None:
        return NOT_RUN, "the K_p = 0 and K_p = 0.001 V/psi runs are missing", (), "", "", False
    ok = best > 2.0 * zero
    text = (
        f"oil-column damping ratio {zero:.3f} at K_p = 0 and {best:.3f} at K_p = 0.001 V/psi "
        f"({best / zero:.1f} times)"
    )
    return (
        (AGREE if ok else DISAGREE),
        text,
        (Curve("table model (first-order delay)", x, y),),
        "K_p [V/psi]",
        "least oil-column damping ratio [-]",
        False,
    )


def _delay_model(rows: SummaryTable) -> tuple:
    diffs, text = [], []
    for tau in (250e-6, 500e-6, 1000e-6):
        fo = _value(rows, "oil_damping_ratio", loop_time=tau, delay="first-order")
        ex = _value(rows, "oil_damping_ratio", loop_time=tau, delay="sampled")
        if fo is None or ex is None:
            return NOT_RUN, f"runs at tau_s = {tau * 1e6:g} us are missing", (), "", "", False
        diffs.append((tau * 1e6, abs(fo - ex) / ex))
        text.append(f"{tau * 1e6:g} us: {100 * diffs[-1][1]:.1f} %")
    ok = (
        diffs[0][1] <= DELAY_MODEL_TOLERANCE
        and diffs[1][1] <= DELAY_MODEL_TOLERANCE
        and diffs[2][1] > diffs[1][1]
    )
    curve = Curve(
        "first-order vs exact sampled-data model", tuple(d[0] for d in diffs), tuple(d[1] for d in diffs)
    )
    limit = Curve(
        f"tolerance {DELAY_MODEL_TOLERANCE:g}", (250.0, 1000.0), (DELAY_MODEL_TOLERANCE,) * 2, "target"
    )
    return (
        (AGREE if ok else DISAGREE),
        "relative error of the oil-column damping: " + ", ".join(text),
        (curve, limit),
        "loop time tau_s [us]",
        "relative error of damping [-]",
        False,
    )


def _kp_model_fidelity(rows: SummaryTable) -> tuple:
    x, y = _points(rows, "K_p", "model_error_10_50hz")
    if len(x) < 3:
        return NOT_RUN, "fewer than three K_p values identified", (), "", "", False
    best = x[min(range(len(y)), key=y.__getitem__)]
    ok = 0.0008 <= best <= 0.0012 and y[0] > min(y)
    text = (
        "rms |log(H_model/H_measured)| 10-50 Hz "
        + ", ".join(f"{e:.3f} at {k:g}" for k, e in zip(x, y))
        + f"; smallest at K_p = {best:g} V/psi"
    )
    return (
        (AGREE if ok else DISAGREE),
        text,
        (Curve("measured FRF vs linear model", x, y),),
        "K_p [V/psi]",
        "rms log error of z/u, 10-50 Hz [-]",
        False,
    )


# ------------------------------------------------------------------ Section 8
def _agreement_by(rows: SummaryTable, key: str, **where: Any) -> dict[float, float]:
    """Smallest spectral agreement frequency over motions, per value of ``key``."""
    out: dict[float, float] = {}
    for row in rows.where(**where).rows:
        value, agreement = row.get(key), row.get("spectral_agreement_hz")
        if isinstance(agreement, (int, float)) and isinstance(value, (int, float)):
            out[float(value)] = min(out.get(float(value), float("inf")), float(agreement))
    return dict(sorted(out.items()))


def _tracking_depths(rows: SummaryTable) -> tuple:
    by_depth = _agreement_by(rows, "water_depth")
    if not by_depth:
        return NOT_RUN, "no tracking runs finished", (), "", "", False
    upto2 = [v for d, v in by_depth.items() if d <= 30.0]
    ok = bool(upto2) and min(upto2) >= 20.0
    text = f"spectra agree (within {AGREEMENT_TOLERANCE:.0%}) up to " + ", ".join(
        f"{v:.1f} Hz at {d:g} in" for d, v in by_depth.items()
    )
    curves = (
        Curve("toolkit: worst of the motions", tuple(by_depth), tuple(by_depth.values())),
        Curve("report: 20 Hz up to 30 in (mass ratio 2)", (0.0, 30.0), (20.0, 20.0), "target"),
    )
    return (AGREE if ok else DISAGREE), text, curves, "water depth [in]", "agreement up to [Hz]", False


def _error_by(rows: SummaryTable, key: str, metric: str, **where: Any) -> dict[Any, float]:
    """Mean of a metric over motions, per value of ``key``."""
    sums: dict[Any, list[float]] = {}
    for row in rows.where(**where).rows:
        value = legacy_value(row, metric)
        if isinstance(value, (int, float)) and row.get("status") == "ok":
            group = row.get(key)
            if key == "feedback" and isinstance(group, str):  # older summaries: load_cells ...
                group = LEGACY_NAMES.get(group, group)
            sums.setdefault(group, []).append(float(value))
    return {k: sum(v) / len(v) for k, v in sums.items()}


def _feedback_sources(rows: SummaryTable) -> tuple:
    err = _error_by(rows, "feedback", "spectral_error_0p25_15hz", water_depth=42.0)
    if Feedback.LOAD_CELLS.value not in err or Feedback.NONE.value not in err:
        return NOT_RUN, "the 42 in runs with load cells and without u_w are missing", (), "", "", False
    ok = err[Feedback.NONE.value] >= MEANINGFUL_RATIO * err[Feedback.LOAD_CELLS.value]
    text = "mean spectral error 0.25-15 Hz at 42 in: " + ", ".join(f"{k} {v:.3g}" for k, v in err.items())
    names = tuple(err)
    curve = Curve("toolkit (mean of motions)", tuple(range(len(names))), tuple(err[n] for n in names))
    return (
        (AGREE if ok else DISAGREE),
        text + " (sources: " + ", ".join(names) + ")",
        (curve,),
        "feedback source (" + ", ".join(f"{i}: {n}" for i, n in enumerate(names)) + ")",
        "spectral error [-]",
        False,
    )


def _worse_than(key: str, worse: float, better: float, label: str, **where: Any) -> Callable:
    """Evaluation: the mean 0.25-15 Hz spectral error at ``key = worse`` is at least
    :data:`MEANINGFUL_RATIO` times that at ``better``."""
    scope = " at 42 in" if where else ""

    def evaluate(rows: SummaryTable) -> tuple:
        err = _error_by(rows, key, "spectral_error_0p25_15hz", **where)
        if worse not in err or better not in err:
            return (
                NOT_RUN,
                f"the runs{scope} at {label} = {worse:g} and {better:g} are missing",
                (),
                "",
                "",
                False,
            )
        x = tuple(sorted(err))
        text = f"mean spectral error 0.25-15 Hz{scope}: " + ", ".join(
            f"{err[k]:.3g} at {label.split(' [')[0]} = {k:g}" for k in x
        )
        curve = Curve("toolkit (mean of motions)", x, tuple(err[k] for k in x))
        ok = err[worse] >= MEANINGFUL_RATIO * err[better]
        return (AGREE if ok else DISAGREE), text, (curve,), label, "spectral error [-]", False

    return evaluate


def _fc_instability(rows: SummaryTable) -> tuple:
    """Footnote 22: at 42 in, tracking is stable up to f_c = 100 Hz and unstable above."""
    state: dict[float, str | None] = {
        float(row["f_c"]): run_stability(row)
        for row in rows.where(water_depth=42.0).rows
        if isinstance(row.get("f_c"), (int, float))
    }
    x, y = _points(rows, "f_c", "hf_ratio", water_depth=42.0)
    below = [f for f in state if f <= 100.0]
    above = [f for f in state if f > 100.0]
    if 100.0 not in state or not above:
        return NOT_RUN, "the 42 in runs at f_c = 100 Hz and above are missing", (), "", "", False
    ok = all(state[f] == "stable" for f in below) and all(state[f] == "unstable" for f in above)
    motions = sorted({str(r.get("motion")) for r in rows.where(water_depth=42.0).rows if r.get("motion")})
    text = f"42 in, {', '.join(motions) or 'motion unrecorded'}: " + ", ".join(
        f"{f:g} Hz {state[f] or 'inconclusive'}" for f in sorted(state)
    )
    text += "; high-frequency rms ratio " + ", ".join(f"{v:.3f} at {f:g} Hz" for f, v in zip(x, y))
    curves = (
        Curve("toolkit", x, y),
        Curve(f"unstable above {HF_UNSTABLE:g}", (min(x), max(x)), (HF_UNSTABLE, HF_UNSTABLE), "other"),
    )
    return (AGREE if ok else DISAGREE), text, curves, "f_c [Hz]", "rms above 15 Hz / rms target [-]", False


def _fe_worse_than_lc(rows: SummaryTable) -> tuple:
    """Section 8.3.2: w_FE tracks as well as w_LC with the empty vessel, worse at 42 in.

    A run that went unstable (:func:`run_stability`) tracks worse than any that did not:
    its error counts as infinite.
    """
    lc, fe = Feedback.LOAD_CELLS.value, Feedback.FORCE_EQUILIBRIUM.value
    err: dict[float, dict[Any, float]] = {}
    for depth in (0.0, 42.0):
        err[depth] = _error_by(rows, "feedback", "spectral_error_0p25_15hz", water_depth=depth)
        for row in rows.where(water_depth=depth).rows:
            if row.get("feedback") in (lc, fe) and run_stability(row) == "unstable":
                err[depth][row["feedback"]] = math.inf
    if any(lc not in e or fe not in e for e in err.values()):
        return (
            NOT_RUN,
            "the 0 and 42 in runs with load cells and force equilibrium are missing",
            (),
            "",
            "",
            False,
        )
    heavy_worse = err[42.0][fe] >= MEANINGFUL_RATIO * err[42.0][lc]
    light_alike = err[0.0][fe] < MEANINGFUL_RATIO * err[0.0][lc]
    text = "mean spectral error 0.25-15 Hz (inf: a run went unstable), fe against lc: " + "; ".join(
        f"{d:g} in {err[d][fe]:.3g} against {err[d][lc]:.3g}" for d in (0.0, 42.0)
    )
    finite = [v for e in err.values() for v in e.values() if math.isfinite(v)]
    top = 2.0 * max(finite, default=1.0)

    def shown(v: float) -> float:
        return v if math.isfinite(v) else top

    curves = (
        Curve("w_LC (load cells)", (0.0, 42.0), (shown(err[0.0][lc]), shown(err[42.0][lc]))),
        Curve("w_FE (force equilibrium)", (0.0, 42.0), (shown(err[0.0][fe]), shown(err[42.0][fe])), "other"),
    )
    return (
        (AGREE if heavy_worse and light_alike else DISAGREE),
        text,
        curves,
        "water depth [in]",
        "spectral error [-] (unstable drawn at twice the largest)",
        False,
    )


# ------------------------------------------------------------------ Section 9
def _mil_band(rows: SummaryTable) -> tuple:
    ok_rows = rows.where(status="ok")
    agreements = ok_rows.values("spectral_agreement_hz")
    if not agreements:
        return NOT_RUN, "no MIL run of Table 9.4 finished", (), "", "", False
    n_good = sum(a >= 15.0 for a in agreements)
    failed = len(rows) - len(ok_rows)
    ok = failed == 0 and n_good >= 0.8 * len(agreements)
    text = (
        f"{n_good} of {len(agreements)} cases agree (within {AGREEMENT_TOLERANCE:.0%}) from 0.25 Hz to "
        f"at least 15 Hz; worst {min(agreements):.1f} Hz; {failed} runs aborted or failed"
    )
    x = tuple(float(i) for i in range(len(agreements)))
    curves = (
        Curve("toolkit, per case", x, tuple(agreements)),
        Curve("report: 15 Hz", (0.0, max(x[-1], 1.0)), (15.0, 15.0), "target"),
    )
    return (AGREE if ok else DISAGREE), text, curves, "case (Table 9.4 order)", "agreement up to [Hz]", False


def _fc_table_9_5(rows: SummaryTable) -> tuple:
    expected = {
        1000.0: (True, False, True),
        250.0: (True, True, True),
        100.0: (True, True, True),
        50.0: (False, True, False),
    }
    got, text = {}, []
    for fc in expected:
        row = rows.where(f_c=fc).rows
        if not row:
            return NOT_RUN, f"the design at f_c = {fc:g} Hz is missing", (), "", "", False
        got[fc] = tuple(bool(row[0].get(k)) for k in ("I", "II", "III"))
        text.append(f"{fc:g} Hz: " + "/".join("S" if v else "N" for v in got[fc]))
    ok = got == expected
    x, y = _points(rows, "f_c", "performance_error")
    _, margin = _points(rows, "f_c", "passivity_tolerant_margin_deg")
    curves = (
        Curve("constraint I: impedance error", x, y),
        Curve("constraint III: passivity margin / 10 deg", x, tuple(m / 10.0 for m in margin), "other"),
    )
    return (
        (AGREE if ok else DISAGREE),
        "constraints I/II/III (S = satisfied): " + "; ".join(text),
        curves,
        "f_c [Hz]",
        "error [-], margin [10 deg]",
        True,
    )


def _trip_cause(row: Mapping[str, Any]) -> TripCause | None:
    """The cause recorded with a run that tripped (column ``trip_limit``); None if none was recorded."""
    label = row.get(TRIP_LIMIT_KEY)
    if not isinstance(label, str) or not label:
        return None
    try:
        return TripCause.from_label(label)
    except ValueError:
        return None


def run_stability(row: Mapping[str, Any]) -> str | None:
    """``"unstable"``, ``"stable"`` or None (inconclusive) for one MIL run.

    Unstable: a trip other than the stroke limit (velocity, force, valve, divergence),
    or table motion above 15 Hz stronger than :data:`HF_UNSTABLE` times the target's
    rms.  A stroke trip alone is inconclusive: the motion may simply need more than
    the +-3 in of the table.  The trip's cause is the recorded :class:`TripCause`,
    never the error message; an aborted run without a recorded cause (a store
    written before causes were recorded) is inconclusive too.
    """
    hf = row.get("hf_ratio")
    if isinstance(hf, (int, float)) and hf > HF_UNSTABLE:
        return "unstable"
    if row.get("status") == "aborted":
        cause = _trip_cause(row)
        return None if cause is None or cause == TripCause.STROKE else "unstable"
    return "stable" if row.get("status") == "ok" else None


#: The report's basemat-mass thresholds at f_c = 80 Hz (Section 9.4.4): the largest m_vs/m_st
#: at which each VS went unstable.  A prediction agrees within +-THRESHOLD_TOLERANCE.
REPORT_THRESHOLDS = {"SD2": 0.7, "LR2": 0.8, "FP2": 0.9}
THRESHOLD_TOLERANCE = 0.1


def _cutoffs(rows: SummaryTable) -> str:
    """The cut-offs f_c the rows ran at, as text (``80 Hz``), read from the runs, not assumed."""
    values = sorted({float(r["f_c"]) for r in rows.rows if isinstance(r.get("f_c"), (int, float))})
    return ", ".join(f"{v:g}" for v in values) + " Hz" if values else "unrecorded"


def _instability_threshold(vs: str) -> Callable:
    """Evaluation: the largest unstable m_vs/m_st of ``vs`` lies within +-0.1 of the report's and
    every larger ratio is stable."""
    reported = REPORT_THRESHOLDS[vs]

    def evaluate(rows: SummaryTable) -> tuple:
        verdicts, by_ratio = {}, {}
        for row in rows.where(vs=vs).rows:
            if isinstance(row.get("m_vs_ratio"), float):
                verdicts[row["m_vs_ratio"]] = run_stability(row)
                by_ratio[row["m_vs_ratio"]] = row
        if not verdicts:
            return NOT_RUN, f"no {vs} basemat-mass run finished", (), "", "", False
        unstable = sorted(r for r, v in verdicts.items() if v == "unstable")
        stable = sorted(r for r, v in verdicts.items() if v == "stable")
        unknown = sorted(r for r, v in verdicts.items() if v is None)
        threshold = max(unstable) if unstable else None
        ok = (
            threshold is not None
            and abs(threshold - reported) <= THRESHOLD_TOLERANCE + 1e-9
            and all(r > threshold for r in stable)
        )
        text = (
            f"{vs}, f_c = {_cutoffs(rows.where(vs=vs))}: unstable at m_vs/m_st = "
            + (", ".join(f"{r:g}" for r in unstable) or "none")
            + "; stable at "
            + (", ".join(f"{r:g}" for r in stable) or "none")
        )
        stroke = [r for r in unknown if _trip_cause(by_ratio[r]) == TripCause.STROKE]
        other = [r for r in unknown if r not in stroke]
        if stroke:
            text += "; inconclusive (stroke trip) at " + ", ".join(f"{r:g}" for r in stroke)
        if other:
            text += "; inconclusive (no trip cause recorded, or not finished) at " + ", ".join(
                f"{r:g}" for r in other
            )
        x = tuple(sorted(r for r, v in verdicts.items() if v is not None))
        curves = (
            Curve("toolkit: 1 = unstable", x, tuple(float(verdicts[r] == "unstable") for r in x)),
            Curve(f"report: unstable at {reported:g}", (reported, reported), (0.0, 1.0), "target"),
        )
        return (AGREE if ok else DISAGREE), text, curves, "m_vs / m_st [-]", "unstable [0/1]", False

    return evaluate


def _fc_recovers(rows: SummaryTable) -> tuple:
    x, y = _points(rows, "f_c", "hf_ratio")
    if len(x) < 2 or x[0] > 80.0 or x[-1] < 200.0:
        return NOT_RUN, "the runs at f_c = 80 and 200 Hz are missing", (), "", "", False
    state = {row.get("f_c"): run_stability(row) for row in rows.rows}
    improved = state.get(80.0) == "unstable" or y[0] >= MEANINGFUL_RATIO * y[-1]
    ok = state.get(200.0) == "stable" and improved
    text = "high-frequency rms ratio " + ", ".join(f"{v:.3f} at {f:g} Hz" for f, v in zip(x, y))
    text += "; " + ", ".join(f"{f:g} Hz {state.get(f) or 'inconclusive'}" for f in x)
    return (
        (AGREE if ok else DISAGREE),
        text,
        (Curve("toolkit", x, y),),
        "f_c [Hz]",
        "rms above 15 Hz / rms target [-]",
        False,
    )


#: Rank correlation of the passivity index with ``hf_ratio`` at or below which "less passive is
#: more oscillatory" holds (a strong monotone trend, tool's choice), with the p-value below.
PASSIVITY_RANK_CORRELATION = -0.5
PASSIVITY_P_VALUE = 0.05


def _passive_oscillatory(rows: SummaryTable) -> tuple:
    x, y = _points(rows, "passivity_index", "hf_ratio")
    if len(x) < 4:
        return (
            NOT_RUN,
            "fewer than 4 MIL runs with a passivity index and hf_ratio finished",
            (),
            "",
            "",
            False,
        )
    rho, p = scipy.stats.spearmanr(x, y)
    ok = bool(rho <= PASSIVITY_RANK_CORRELATION and p < PASSIVITY_P_VALUE)
    answer = "yes: the less passive designs oscillate more" if ok else "no clear trend"
    text = (
        f"{len(x)} runs: Spearman rank correlation of the passivity index (min Re 1/H_vw, "
        f"{min(x):.3g} to {max(x):.3g} lbf*s/in) with the rms above 15 Hz over the target's "
        f"({min(y):.3g} to {max(y):.3g}) is {rho:.2f} (p = {p:.2g}): {answer}"
    )
    curves = (Curve("toolkit: one MIL run", x, y),)
    return (
        (AGREE if ok else DISAGREE),
        text,
        curves,
        "passivity index [lbf*s/in]",
        "rms above 15 Hz / rms target [-]",
        False,
    )


#: The claims of the report checked by the reproduction suite, in report order.
CLAIMS: tuple[Claim, ...] = (
    Claim(
        "sec4-dp-damping",
        "4.4.3, Contribution #3",
        "Delta-P feedback with a sufficiently large gain adds damping to the oil-column resonance.",
        "report-sec4",
        "kp-poles",
        "least-damped pole pair of the table model: damping at K_p = 0.001 V/psi more than twice that at K_p = 0.",
        _kp_damping,
    ),
    Claim(
        "sec4-delay-model",
        "4.5.3.3",
        "For loop times up to 500 us the first-order approximation of the sampling delay is accurate; "
        "for 1000 us it becomes unreliable.",
        "report-sec4",
        "delay-model",
        f"oil-column damping of the first-order model within {DELAY_MODEL_TOLERANCE:.0%} of the exact "
        "sampled-data model at 250 and 500 us, and further off at 1000 us.",
        _delay_model,
    ),
    Claim(
        "sec4-kp-fidelity",
        "4.5.4, Figure 4.16",
        "K_p = 0.001 V/psi gives the most faithful linear model: poor at 0.0002, better at 0.0006, "
        "best at 0.001, deteriorating at 0.0014 V/psi.",
        "report-sec4",
        "kp-frf",
        "multisine FRF z/u of the virtual table with the 36 in vessel against the linear model "
        "(Section 4.5.4 method): smallest rms log error over 10-50 Hz for K_p in 0.0008-0.0012 V/psi.",
        _kp_model_fidelity,
    ),
    Claim(
        "sec8-tracking-20hz",
        "8.3.1, Contribution #7",
        "The table tracks the input accurately up to 20 Hz for mass ratios up to 2 (water depth up to "
        "30 in), with slightly reduced accuracy at 2.5.",
        "report-sec8",
        "depths",
        f"5%-damped spectra of table and input agree within {AGREEMENT_TOLERANCE:.0%} from 0.25 Hz to at "
        "least 20 Hz for every motion at 0, 18 and 30 in.",
        _tracking_depths,
    ),
    Claim(
        "sec8-feedback",
        "8.3.2",
        "At a mass ratio of 2.5 the compensation u_w is essential: without it tracking is poor.",
        "report-sec8",
        "feedback",
        f"at 42 in, the mean spectral error 0.25-15 Hz without u_w is at least {MEANINGFUL_RATIO:g} times "
        "that with load-cell feedback.",
        _feedback_sources,
    ),
    Claim(
        "sec8-kp",
        "8.3.3",
        "K_p = 0.0002 V/psi tracks poorly above 5 Hz; a sufficiently large K_p (0.001 V/psi) tracks well.",
        "report-sec8",
        "kp",
        f"mean spectral error 0.25-15 Hz at K_p = 0.0002 at least {MEANINGFUL_RATIO:g} times that at "
        "0.001 V/psi.",
        _worse_than("K_p", 0.0002, 0.001, "K_p [V/psi]"),
    ),
    Claim(
        "sec8-fc",
        "8.3.4",
        "At a mass ratio of 2.5, f_c = 40 Hz tracks poorly and tracking improves at 80 Hz.",
        "report-sec8",
        "fc",
        f"at 42 in, the mean spectral error 0.25-15 Hz at f_c = 40 Hz at least {MEANINGFUL_RATIO:g} times "
        "that at 80 Hz.",
        _worse_than("f_c", 40.0, 80.0, "f_c [Hz]", water_depth=42.0),
    ),
    Claim(
        "sec8-fc-instability",
        "8.3.4, footnote 22",
        "When the table imitates the ground motion as-is (z_vs = a_g), f_c > 100 Hz resulted in a highly "
        "oscillatory table response indicating instability.",
        "report-sec8",
        "fc-high",
        f"tracking at 42 in (GM1): stable at every f_c up to 100 Hz and unstable at every f_c above (a trip "
        f"other than stroke, or rms above 15 Hz more than {HF_UNSTABLE:g} times the target's).",
        _fc_instability,
    ),
    Claim(
        "sec8-fe-vs-lc",
        "8.3.2, Figures 8.7-8.9",
        "w_LC and w_FE both track acceptably for small mass ratios, but with a heavy article (mass ratio 2.5) "
        "w_FE tracks inaccurately from 5 to 20 Hz.",
        "report-sec8",
        "feedback",
        f"mean spectral error 0.25-15 Hz with w_FE at least {MEANINGFUL_RATIO:g} times that with w_LC at 42 in, "
        "and less than that with the empty vessel.",
        _fe_worse_than_lc,
    ),
    Claim(
        "sec9-band",
        "9.3, Contribution #8",
        "MIL is accurate from 0.25 to 15 Hz for the 27 cases of Table 9.4, with reduced accuracy above.",
        "report-sec9",
        "table-9.4",
        f"table and VS-target spectra agree within {AGREEMENT_TOLERANCE:.0%} from 0.25 Hz to at least 15 Hz "
        "in at least 80 % of the cases, and no run aborts.",
        _mil_band,
    ),
    Claim(
        "sec9-table-9.5",
        "9.4.3, Table 9.5",
        "For SD2 (m_vs = 1.25 m_st): f_c = 1000 Hz violates constraint II; 250 and 100 Hz satisfy all; "
        "50 Hz violates constraints I and III.",
        "report-sec9",
        "design-fc",
        "constraints I, II, III of the designed controller at each f_c equal Table 9.5.",
        _fc_table_9_5,
    ),
    Claim(
        "sec9-basemat-mass",
        "9.4.4, Figure 9.34",
        "For SD2 at f_c = 80 Hz the MIL system becomes unstable when the basemat mass is reduced to "
        "0.7 m_st (0.8 m_st for LR2, 0.9 m_st for FP2).",
        "report-sec9",
        "basemat-mass",
        "SD2 MIL runs: the largest unstable m_vs/m_st (a trip other than stroke, or rms above 15 Hz larger "
        "than the target's) lies in 0.6-0.8 and every larger ratio is stable.",
        _instability_threshold("SD2"),
    ),
    Claim(
        "sec9-basemat-mass-lr2",
        "9.4.4",
        "For f_c = 80 Hz the threshold basemat mass triggering instability is 0.8 m_st for LR2.",
        "report-sec9",
        "basemat-mass",
        "LR2 MIL runs: the largest unstable m_vs/m_st lies in 0.7-0.9 and every larger ratio is stable.",
        _instability_threshold("LR2"),
    ),
    Claim(
        "sec9-basemat-mass-fp2",
        "9.4.4",
        "For f_c = 80 Hz the threshold basemat mass triggering instability is 0.9 m_st for FP2.",
        "report-sec9",
        "basemat-mass",
        "FP2 MIL runs: the largest unstable m_vs/m_st lies in 0.8-1.0 and every larger ratio is stable.",
        _instability_threshold("FP2"),
    ),
    Claim(
        "sec9-fc-recovery",
        "9.4.5, Figure 9.35",
        "At m_vs = 0.7 m_st, raising f_c from 80 Hz to 200 Hz reduces the high-frequency oscillations "
        "and restores MIL performance.",
        "report-sec9",
        "fc-recovery",
        f"SD2 at 0.7 m_st: the run at 200 Hz is stable and the 80 Hz run is unstable or has at least "
        f"{MEANINGFUL_RATIO:g} times its high-frequency content.",
        _fc_recovers,
    ),
    Claim(
        "sec10-passive-oscillatory",
        "10.4 (a question of the report's future work)",
        "Does less passive mean more oscillatory? The report asks whether the degree of passivity of the "
        "controlled table predicts the high-frequency oscillation of a MIL test.",
        "report-sec9",
        "table-9.4",
        f"the MIL runs of Table 9.4 (f_c = 80 Hz): 'agree' (yes) when the Spearman rank correlation of the "
        f"design's passivity index with hf_ratio is at most {PASSIVITY_RANK_CORRELATION:g} with "
        f"p < {PASSIVITY_P_VALUE:g}.",
        _passive_oscillatory,
    ),
)


def evaluate_claims(tables: Sequence[SummaryTable], claims: Sequence[Claim] = CLAIMS) -> list[ClaimOutcome]:
    """Evaluate every claim on the rows of its study found in the given summaries.

    Parameters
    ----------
    tables : sequence of SummaryTable
        Summaries of campaign folders (any campaigns; rows are found by study name).
    claims : sequence of Claim
        The claims (default: :data:`CLAIMS`).
    """
    outcomes = []
    for claim in claims:
        rows = tuple(row for table in tables for row in table.where(study=claim.study).rows)
        finished = SummaryTable(
            _columns(tables), tuple(r for r in rows if r.get("status") in ("ok", "aborted"))
        )
        if not len(finished):
            why = (
                "no finished run of study "
                + repr(claim.study)
                + (
                    f" ({len(rows)} runs failed or pending)"
                    if rows
                    else f"; run `imil campaign run {claim.campaign}`"
                )
            )
            outcomes.append(ClaimOutcome(claim, NOT_RUN, why))
            continue
        verdict, measured, curves, xlabel, ylabel, xlog = claim.evaluate(finished)
        outcomes.append(ClaimOutcome(claim, verdict, measured, tuple(curves), xlabel, ylabel, xlog))
    return outcomes


def _columns(tables: Sequence[SummaryTable]) -> tuple[str, ...]:
    seen: dict[str, None] = {}
    for table in tables:
        seen.update(dict.fromkeys(table.columns))
    return tuple(seen)


def verdict_counts(outcomes: Sequence[ClaimOutcome]) -> Mapping[str, int]:
    """Number of claims per verdict."""
    return {v: sum(o.verdict == v for o in outcomes) for v in (AGREE, DISAGREE, NOT_RUN)}
