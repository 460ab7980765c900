"""Worst-case margins of a design over an uncertainty set (issue 17, item 3).

The reference is the design itself: a degenerate set reproduces the margins
the design reports (constraint III and the sampled-data margin of
``with_indices``) exactly, the same functions on the same table; a set
containing the nominal point can only do worse (the nominal is one of its
points); a set reaching 5 loops of output delay makes the report's table loop
unstable (closed-loop poles of ``LinearTable``: 53 Hz, real part +19 rad/s).
"""

from __future__ import annotations

import pytest

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.design.optimized import with_indices
from impedance_mil.design.robust import robust_margins
from impedance_mil.plant import TableParameters
from impedance_mil.plant.uncertainty import parse_uncertainty
from impedance_mil.specimens import FluidVessel
from impedance_mil.virtual import presets

P = TableParameters.report_default()
VM = virtual_model(presets.get("SD2"))
VESSEL = FluidVessel(36.0).impedance()


@pytest.fixture(scope="module")
def design():
    d = design_controller(table_model(P), VM, form="standardized", fc_hz=80.0, emit_warnings=False)
    return with_indices(d, P, VM, warn=False)


def test_degenerate_set_reproduces_the_nominal_margins(design):
    box = parse_uncertainty({"f_oil_hz": {"min": "27 Hz", "max": "27 Hz"}, "zeta_oil": "±0 %"}, P)
    r = robust_margins(design, P, VM, box, VESSEL, "vessel 36 in", samples=3)
    c = design.constraint_at(80.0)
    for p in (r.nominal, r.worst_passivity, r.worst_coupled, r.worst_sampled):
        assert p.passivity_margin_deg == c.passivity_margin_deg
        assert p.tolerant_margin_deg == c.passivity_tolerant_margin_deg
        assert p.sampled_margin_deg == c.passivity_margin_sampled_deg
    assert r.robustly_passive == c.III
    assert len(r.points) == 1 + 1 + 3  # nominal, the one vertex, the sample


def test_a_set_containing_the_nominal_is_no_better(design):
    box = parse_uncertainty({"f_oil_hz": "±10 %", "extra_delay": {"min": 0, "max": 1}}, P)
    r = robust_margins(design, P, VM, box, VESSEL, "vessel 36 in", samples=4, seed=1)
    assert r.worst_passivity.tolerant_margin_deg <= r.nominal.tolerant_margin_deg
    assert r.worst_coupled.coupled_margin <= r.nominal.coupled_margin
    assert r.worst_sampled.sampled_margin_deg <= r.nominal.sampled_margin_deg
    assert r.vertices == 4 and r.lhs_samples == 4
    # one more loop of delay costs phase: the worst passivity point has it (measured -5.55 deg there)
    assert r.worst_passivity.point["extra_delay"] == 1.0
    assert r.worst_passivity.tolerant_margin_deg < r.nominal.tolerant_margin_deg - 1.0
    assert r.binding in ("passivity", "sampled passivity", "coupled stability")


def test_large_extra_delay_is_not_robust(design):
    box = parse_uncertainty({"extra_delay": {"min": 0, "max": 4}}, P)
    r = robust_margins(design, P, VM, box, VESSEL, "vessel 36 in", samples=2)
    assert r.nominal.coupled.stable
    assert not r.robustly_stable and not r.robustly_passive
    assert r.worst_coupled.point["extra_delay"] == 4.0
    assert r.worst_coupled.coupled.max_real_part > 0
    assert "NOT robustly stable" in r.line()
    doc = r.to_dict()
    assert doc["robustly_stable"] is False and doc["worst"]["parameters"]["extra_delay_loops"] == 4.0
