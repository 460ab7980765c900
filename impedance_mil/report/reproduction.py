"""The reproduction report: each claim of the report against the toolkit's campaigns.

:func:`write_reproduction_report` reads the summaries of one or more campaign
folders (e.g. of ``report-sec4``, ``report-sec8``, ``report-sec9``),
evaluates :data:`impedance_mil.campaign.claims.CLAIMS` on them and writes a
self-contained HTML page: for each claim, the report's statement with its
section, the toolkit's figure (inline SVG) and numbers, and the verdict
(agree, disagree, not run).  The claims are data; this module only draws them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from matplotlib.figure import Figure

from .. import __version__
from ..campaign.claims import AGREE, CLAIMS, DISAGREE, NOT_RUN, Claim, ClaimOutcome, evaluate_claims
from ..campaign.store import CampaignStore
from ..campaign.summary import NOT_RUN as RUN_NOT_RUN
from ..campaign.summary import SummaryTable, load_summary
from ..errors import ConfigError, ImilError
from ..lab.calibration_record import CalibrationRecord
from ..lab.labfile import load_lab
from .html import STYLES, escape, figure_svg, html_page, new_figure, write_html


@dataclass(frozen=True)
class ReproductionResult:
    """What the reproduction report found.

    Attributes
    ----------
    path : Path
        The HTML file written.
    outcomes : tuple of ClaimOutcome
        One per claim, in report order.
    """

    path: Path
    outcomes: tuple[ClaimOutcome, ...]
    #: The calibration records of the calibrated labs the campaigns ran on (empty: none).
    calibrations: tuple[CalibrationRecord, ...] = ()

    def role(self, outcome: ClaimOutcome) -> str:
        """``calibrated`` (its agreement does not count), ``predicted``, or ``""`` (no calibrated lab)."""
        return claim_role(outcome.claim, self.calibrations)

    @property
    def predicted_agree(self) -> int:
        """Claims predicted by a calibrated lab (not calibrated on) that agree."""
        return sum(o.verdict == AGREE and self.role(o) == PREDICTED for o in self.outcomes)

    def _count(self, verdict: str) -> int:
        return sum(o.verdict == verdict for o in self.outcomes)

    @property
    def agree(self) -> int:
        """Claims the toolkit agrees with."""
        return self._count(AGREE)

    @property
    def disagree(self) -> int:
        """Claims the toolkit disagrees with."""
        return self._count(DISAGREE)

    @property
    def not_run(self) -> int:
        """Claims without data."""
        return self._count(NOT_RUN)


CALIBRATED, PREDICTED = "calibrated", "predicted"


def claim_role(claim: Claim, calibrations: Sequence[CalibrationRecord]) -> str:
    """Whether ``claim`` was calibrated on, predicted, or neither (no calibrated lab in the campaigns)."""
    if not calibrations:
        return ""
    return CALIBRATED if any(r.claim == claim.id for r in calibrations) else PREDICTED


def lab_calibrations(tables: Sequence[SummaryTable]) -> tuple[CalibrationRecord, ...]:
    """The ``[calibration]`` records of the lab files the runs name (column ``lab``).

    Raises
    ------
    ConfigError
        A lab the runs name cannot be read: which claim it was calibrated on cannot be told,
        so no claim could be marked calibrated or predicted honestly.
    """
    names = sorted({str(v) for t in tables if "lab" in t.columns for v in t.column("lab") if v})
    records = []
    for name in names:
        try:
            record = load_lab(name).calibration
        except ImilError as exc:
            raise ConfigError(
                f"lab {name}",
                "the lab file the runs were made on, readable from here (it says which claim it was "
                f"calibrated on): {exc}",
            ) from None
        if record is not None and record not in records:
            records.append(record)
    return tuple(records)


def claim_figure(outcome: ClaimOutcome) -> Figure:
    """The figure of one claim: the toolkit's curves (blue) and the report's values (dashed red)."""
    fig, (ax,) = new_figure(width=6.0, height=3.4)
    for curve in outcome.curves:
        style = dict(STYLES.get(curve.role, STYLES["other"]))
        ax.plot(
            curve.x,
            curve.y,
            marker="o" if curve.role != "target" else None,
            markersize=4,
            label=curve.label,
            **style,
        )
    if outcome.xlog:
        ax.set_xscale("log")
    ax.set_xlabel(outcome.xlabel)
    ax.set_ylabel(outcome.ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title(f"{outcome.claim.id} (report Section {outcome.claim.section})", fontsize="medium")
    return fig


def _claim_section(outcome: ClaimOutcome, role: str) -> str:
    claim: Claim = outcome.claim
    css = outcome.verdict.replace(" ", "-")
    tag = {
        CALIBRATED: " (calibrated on this claim: its agreement does not count)",
        PREDICTED: " (predicted, not calibrated on)",
    }.get(role, "")
    parts = [
        f'<div class="claim" id="{escape(claim.id)}">',
        f'<h2>{escape(claim.id)} <span class="verdict {css}">{escape(outcome.verdict)}</span>{escape(tag)}</h2>',
        f"<p><b>Report, Section {escape(claim.section)}:</b></p><blockquote>{escape(claim.statement)}</blockquote>",
        f"<p><b>Test:</b> {escape(claim.test)} (campaign <code>{escape(claim.campaign)}</code>, "
        f"study <code>{escape(claim.study)}</code>)</p>",
        f"<p><b>Toolkit:</b> {escape(outcome.measured)}</p>",
    ]
    if outcome.curves:
        parts.append(figure_svg(claim_figure(outcome)))
    parts.append("</div>")
    return "".join(parts)


def _overview(outcomes: Sequence[ClaimOutcome], calibrations: Sequence[CalibrationRecord]) -> str:
    roles = {o.claim.id: claim_role(o.claim, calibrations) for o in outcomes}
    rows = "".join(
        f'<tr><td><a href="#{escape(o.claim.id)}">{escape(o.claim.id)}</a></td>'
        f"<td>{escape(o.claim.section)}</td><td>{escape(o.claim.statement)}</td>"
        f"<td>{escape(roles[o.claim.id] or '-')}</td>"
        f'<td><span class="verdict {o.verdict.replace(" ", "-")}">{escape(o.verdict)}</span></td></tr>'
        for o in outcomes
    )
    counts = {v: sum(o.verdict == v for o in outcomes) for v in (AGREE, DISAGREE, NOT_RUN)}
    summary = ", ".join(f"{n} {v}" for v, n in counts.items())
    text = f"<h2>Overview</h2><p>{len(outcomes)} claims: {escape(summary)}.</p>"
    for record in calibrations:
        predicted = [o for o in outcomes if roles[o.claim.id] == PREDICTED and o.verdict != NOT_RUN]
        good = sum(o.verdict == AGREE for o in predicted)
        text += (
            f"<p><b>Calibrated lab:</b> {escape(record.parameter)} = {escape(record.value)}, calibrated on "
            f'<a href="#{escape(record.claim)}">{escape(record.claim)}</a> '
            f"({'reproduced' if record.reproduced else 'NOT reproduced'} within its sources' range; protocol "
            f"<code>{escape(record.protocol)}</code>). Agreement on that claim does not count; "
            f"{good} of {len(predicted)} predicted claims that were run agree.</p>"
        )
    return (
        text + "<table><tr><th>claim</th><th>section</th><th>statement</th><th>role</th><th>verdict</th></tr>"
        f"{rows}</table>"
    )


def _inventory(folders: Sequence[Path], tables: Sequence[SummaryTable]) -> str:
    rows = []
    for folder, table in zip(folders, tables):
        name = folder.name
        try:
            manifest = CampaignStore(folder).read_json("campaign.json")
            name = f"{manifest.get('name', name)}{' (reduced)' if manifest.get('reduced') else ''}"
        except (OSError, ValueError):
            pass
        statuses = table.column("status")
        counts = ", ".join(
            f"{s} {statuses.count(s)}" for s in ("ok", "aborted", "failed", RUN_NOT_RUN) if statuses.count(s)
        )
        rows.append(
            f'<tr><td>{escape(name)}</td><td>{escape(folder)}</td><td class="num">{len(table)}</td>'
            f"<td>{escape(counts)}</td></tr>"
        )
    return (
        "<h2>Campaigns read</h2><table><tr><th>campaign</th><th>folder</th><th>runs</th>"
        f"<th>status</th></tr>{''.join(rows)}</table>"
    )


def render_reproduction_html(
    folders: Sequence[str | Path], claims: Sequence[Claim] = CLAIMS
) -> tuple[str, list[ClaimOutcome], tuple[CalibrationRecord, ...]]:
    """The reproduction page for campaign folders, the claim outcomes and the labs' calibration records.

    Raises
    ------
    DataFileError
        A folder is not a campaign folder.
    """
    paths = [Path(f) for f in folders]
    tables = [load_summary(p) for p in paths]
    outcomes = evaluate_claims(tables, claims)
    calibrations = lab_calibrations(tables)
    intro = (
        "<p>Each claim of the MCEER report <i>Impedance-Matching Control Design for Shake-Table "
        "Testing and Model-in-the-Loop Simulations</i> is quoted with its section, then tested on "
        "the virtual lab's campaigns. <b>agree</b>: the toolkit's numbers support the statement; "
        "<b>disagree</b>: they do not; <b>not run</b>: the campaign holding the data was not run "
        "(or its runs failed). Toolkit curves are solid blue, the report's values dashed red. When the "
        "campaigns ran on a calibrated lab (<code>imil campaign calibrate</code>), the claim it was "
        "calibrated on is marked <i>calibrated</i> and its agreement does not count; the others are "
        "<i>predicted</i>.</p>"
    )
    sections = (
        [intro, _overview(outcomes, calibrations)]
        + [_claim_section(o, claim_role(o.claim, calibrations)) for o in outcomes]
        + [_inventory(paths, tables)]
    )
    page = html_page("Reproduction of the report's claims", sections, subtitle=f"impedance-mil {__version__}")
    return page, outcomes, calibrations


def write_reproduction_report(
    folders: Sequence[str | Path], out: str | Path, claims: Sequence[Claim] = CLAIMS
) -> ReproductionResult:
    """Write the reproduction page for campaign folders to ``out`` (atomically).

    Parameters
    ----------
    folders : sequence of path
        Campaign folders (written by ``imil campaign run``).
    out : path
        HTML file to write.
    claims : sequence of Claim
        The claims to check (default: all of :data:`~impedance_mil.campaign.claims.CLAIMS`).
    """
    page, outcomes, calibrations = render_reproduction_html(folders, claims)
    return ReproductionResult(write_html(out, page), tuple(outcomes), calibrations)
