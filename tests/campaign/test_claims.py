"""The claims' evaluations on hand-made summary rows: each can agree, disagree, or say not run."""

from __future__ import annotations

from impedance_mil.campaign.claims import AGREE, CLAIMS, DISAGREE, NOT_RUN, evaluate_claims
from impedance_mil.campaign.summary import SummaryTable

BY_ID = {c.id: c for c in CLAIMS}


def table(study, rows):
    full = [
        {"run_id": f"r{i}", "study": study, "status": "ok", "error": "", "hdf5": "", "elapsed_s": 0.1, **row}
        for i, row in enumerate(rows)
    ]
    columns = tuple(dict.fromkeys(k for row in full for k in row))
    return SummaryTable(columns, tuple(full))


def verdict(claim_id, tables):
    (outcome,) = evaluate_claims(tables, [BY_ID[claim_id]])
    return outcome


def test_every_claim_is_not_run_without_data():
    outcomes = evaluate_claims([])
    assert [o.verdict for o in outcomes] == [NOT_RUN] * len(CLAIMS)
    assert all("imil campaign run report-sec" in o.measured for o in outcomes)


def test_claims_name_their_section_and_a_builtin_campaign():
    assert len({c.id for c in CLAIMS}) == len(CLAIMS)
    assert all(c.section and c.campaign.startswith("report-sec") for c in CLAIMS)


def test_table_9_5_pattern():
    # Table 9.5: 1000 Hz S/N/S, 250 S/S/S, 100 S/S/S, 50 N/S/N.
    pattern = {
        1000.0: (True, False, True),
        250.0: (True, True, True),
        100.0: (True, True, True),
        50.0: (False, True, False),
    }
    rows = [
        {
            "f_c": fc,
            "I": i,
            "II": ii,
            "III": iii,
            "performance_error": 0.1,
            "passivity_tolerant_margin_deg": 1.0,
        }
        for fc, (i, ii, iii) in pattern.items()
    ]
    assert verdict("sec9-table-9.5", [table("design-fc", rows)]).verdict == AGREE
    rows[3]["III"] = True
    assert verdict("sec9-table-9.5", [table("design-fc", rows)]).verdict == DISAGREE


def test_basemat_mass_threshold():
    def rows(unstable, limit="divergence"):
        return [
            {
                "vs": "SD2",
                "m_vs_ratio": r,
                "status": "aborted" if r in unstable else "ok",
                "error": f"limit '{limit}' tripped at t = 1 s" if r in unstable else "",
                "trip_limit": limit if r in unstable else None,
                "hf_ratio": 0.1,
            }
            for r in (1.25, 1.0, 0.9, 0.8, 0.7)
        ]

    assert verdict("sec9-basemat-mass", [table("basemat-mass", rows({0.7}))]).verdict == AGREE
    # Unstable already at 0.9 (as the passivity design check suggests): the report's 0.7 is not reproduced.
    outcome = verdict("sec9-basemat-mass", [table("basemat-mass", rows({0.9, 0.8, 0.7}))])
    assert outcome.verdict == DISAGREE and "unstable at m_vs/m_st = 0.7, 0.8, 0.9" in outcome.measured
    # A stroke trip alone is inconclusive (the motion may need more than +-3 in).
    stroke = verdict("sec9-basemat-mass", [table("basemat-mass", rows({0.9, 0.7}, "stroke"))])
    assert stroke.verdict == DISAGREE and "inconclusive (stroke trip) at 0.7, 0.9" in stroke.measured
    # Strong high-frequency oscillation without a trip also counts as unstable.
    oscillating = rows(set())
    oscillating[-1]["hf_ratio"] = 3.0
    assert verdict("sec9-basemat-mass", [table("basemat-mass", oscillating)]).verdict == AGREE


def test_stability_follows_the_recorded_cause_not_the_message():
    # The verdict reads the trip cause recorded with the run (its trip_limit column, a
    # TripCause name), never the error text: a message naming the stroke with a velocity
    # cause is unstable, one naming the velocity with a stroke cause is inconclusive, and
    # an aborted run without a recorded cause is inconclusive whatever its message says.
    def rows(aborted):
        ok = [{"vs": "SD2", "m_vs_ratio": r, "hf_ratio": 0.1} for r in (1.25, 1.0, 0.9, 0.8)]
        return ok + [{"vs": "SD2", "m_vs_ratio": 0.7, "hf_ratio": 0.1, "status": "aborted", **aborted}]

    def outcome(aborted):
        return verdict("sec9-basemat-mass", [table("basemat-mass", rows(aborted))])

    velocity = outcome({"error": "limit 'stroke' tripped at t = 1 s", "trip_limit": "velocity"})
    assert velocity.verdict == AGREE and "unstable at m_vs/m_st = 0.7;" in velocity.measured
    stroke = outcome({"error": "limit 'velocity' tripped at t = 1 s", "trip_limit": "stroke"})
    assert stroke.verdict == DISAGREE and "inconclusive (stroke trip) at 0.7" in stroke.measured
    unrecorded = outcome({"error": "limit 'velocity' tripped at t = 1 s"})
    assert unrecorded.verdict == DISAGREE and "no trip cause recorded" in unrecorded.measured


def test_mil_band_needs_15_hz_in_most_cases():
    good = [{"spectral_agreement_hz": 18.0} for _ in range(27)]
    assert verdict("sec9-band", [table("table-9.4", good)]).verdict == AGREE
    poor = [{"spectral_agreement_hz": 18.0 if i < 20 else 9.0} for i in range(27)]
    outcome = verdict("sec9-band", [table("table-9.4", poor)])
    assert outcome.verdict == DISAGREE and "20 of 27" in outcome.measured


def test_tracking_kp_compares_the_mean_over_motions():
    rows = [
        {"K_p": kp, "motion": gm, "spectral_error_low": err}
        for kp, err in ((0.0002, 0.6), (0.001, 0.1))
        for gm in ("GM1", "GM2")
    ]
    assert verdict("sec8-kp", [table("kp", rows)]).verdict == AGREE
    for row in rows:
        row["spectral_error_low"] = 0.1 if row["K_p"] == 0.0002 else 0.6
    assert verdict("sec8-kp", [table("kp", rows)]).verdict == DISAGREE
    # A difference at the noise level (0.0301 vs 0.0300) is not "poor against accurate".
    for row in rows:
        row["spectral_error_low"] = 0.0301 if row["K_p"] == 0.0002 else 0.0300
    assert verdict("sec8-kp", [table("kp", rows)]).verdict == DISAGREE


def test_failed_runs_leave_a_claim_not_run_and_say_so():
    rows = [{"K_p": 0.001, "status": "failed"}]
    outcome = verdict("sec8-kp", [table("kp", rows)])
    assert outcome.verdict == NOT_RUN and "1 runs failed or pending" in outcome.measured


def test_less_passive_more_oscillatory_needs_a_strong_monotone_trend():
    # Section 10.4's question on hand-made rows: hf_ratio falling as the index rises (less
    # passive, more oscillatory) agrees; no order disagrees; fewer than 4 runs is not run.
    index = [-80.0, -75.0, -70.0, -65.0, -60.0, -55.0]
    trend = table("table-9.4", [{"passivity_index": i, "hf_ratio": 0.3 - 0.004 * (i + 80)} for i in index])
    out = verdict("sec10-passive-oscillatory", [trend])
    assert out.verdict == AGREE and "-1.00" in out.measured
    flat = [0.10, 0.02, 0.15, 0.03, 0.12, 0.05]
    mixed = table("table-9.4", [{"passivity_index": i, "hf_ratio": h} for i, h in zip(index, flat)])
    assert verdict("sec10-passive-oscillatory", [mixed]).verdict == DISAGREE
    few = table("table-9.4", [{"passivity_index": i, "hf_ratio": 0.1} for i in index[:3]])
    assert verdict("sec10-passive-oscillatory", [few]).verdict == NOT_RUN


def test_basemat_mass_thresholds_of_lr2_and_fp2_use_their_own_report_value():
    # Section 9.4.4: LR2 unstable from 0.8 m_st, FP2 from 0.9 m_st; each within +-0.1.
    def rows(vs, unstable):
        return [
            {"vs": vs, "m_vs_ratio": r, "hf_ratio": 3.0 if r in unstable else 0.1}
            for r in (1.25, 1.0, 0.9, 0.8, 0.7, 0.6)
        ]

    lr2 = table("basemat-mass", rows("LR2", {0.8, 0.7, 0.6}))
    assert verdict("sec9-basemat-mass-lr2", [lr2]).verdict == AGREE
    # The SD2 claim finds no SD2 row in the same study.
    assert verdict("sec9-basemat-mass", [lr2]).verdict == NOT_RUN
    assert (
        verdict("sec9-basemat-mass-fp2", [table("basemat-mass", rows("FP2", {0.9, 0.8, 0.7, 0.6}))]).verdict
        == AGREE
    )
    # FP2 unstable only from 0.7: 0.2 below the report's 0.9.
    late = verdict("sec9-basemat-mass-fp2", [table("basemat-mass", rows("FP2", {0.7, 0.6}))])
    assert late.verdict == DISAGREE and "unstable at m_vs/m_st = 0.6, 0.7" in late.measured


def test_fc_instability_needs_stable_up_to_100_hz_and_unstable_above():
    def rows(unstable):
        return [
            {"water_depth": 42.0, "f_c": fc, "hf_ratio": 2.0 if fc in unstable else 0.2}
            for fc in (80.0, 100.0, 150.0, 200.0)
        ]

    assert verdict("sec8-fc-instability", [table("fc-high", rows({150.0, 200.0}))]).verdict == AGREE
    # The virtual lab before issue 17: stable everywhere.
    benign = verdict("sec8-fc-instability", [table("fc-high", rows(set()))])
    assert benign.verdict == DISAGREE and "150 Hz stable" in benign.measured
    # Unstable already at 100 Hz: not the report's observation either.
    early = verdict("sec8-fc-instability", [table("fc-high", rows({100.0, 150.0, 200.0}))])
    assert early.verdict == DISAGREE
    assert verdict("sec8-fc-instability", [table("fc-high", rows(set())[:2])]).verdict == NOT_RUN


def test_force_equilibrium_is_worse_only_with_the_heavy_article():
    def rows(fe_light, fe_heavy):
        return [
            {"water_depth": d, "feedback": fb, "motion": "GM1", "spectral_error_0p25_15hz": e}
            for d, fb, e in (
                (0.0, "lc", 0.1),
                (0.0, "fe", fe_light),
                (42.0, "lc", 0.1),
                (42.0, "fe", fe_heavy),
            )
        ]

    assert verdict("sec8-fe-vs-lc", [table("feedback", rows(0.11, 0.2))]).verdict == AGREE
    alike = verdict("sec8-fe-vs-lc", [table("feedback", rows(0.11, 0.11))])
    assert alike.verdict == DISAGREE and "42 in 0.11 against 0.1" in alike.measured
    assert verdict("sec8-fe-vs-lc", [table("feedback", rows(0.2, 0.2))]).verdict == DISAGREE


def test_an_unstable_force_equilibrium_run_tracks_worse():
    # The what-if of docs/campaign.md: w_FE went unstable with the empty vessel (command-slew
    # trip), so it is not "as good as w_LC" there, whatever its error before the trip.
    rows = [
        {"water_depth": d, "feedback": fb, "motion": "GM1", "spectral_error_0p25_15hz": 0.1}
        for d in (0.0, 42.0)
        for fb in ("lc", "fe")
    ]
    rows[1].update(status="aborted", trip_limit="command_oscillation")
    outcome = verdict("sec8-fe-vs-lc", [table("feedback", rows)])
    assert outcome.verdict == DISAGREE and "0 in inf against 0.1" in outcome.measured
    rows[1].update(status="ok", trip_limit=None)
    rows[3].update(status="aborted", trip_limit="command_oscillation")
    assert verdict("sec8-fe-vs-lc", [table("feedback", rows)]).verdict == AGREE
