"""Fixtures of the command-line tests shared by the bad-input corpora."""

from __future__ import annotations

import json

import pytest

from impedance_mil.design import design_controller, save_design, table_model, virtual_model
from impedance_mil.plant import TableParameters
from impedance_mil.virtual import presets


@pytest.fixture(scope="session")
def sd2_design_text(tmp_path_factory) -> str:
    """A valid design file's text: SD2 on the report's table, standardized form at fc = 80 Hz."""
    design = design_controller(
        table_model(TableParameters.report_default()),
        virtual_model(presets.get("SD2")),
        form="standardized",
        fc_hz=80.0,
        emit_warnings=False,
    )
    return save_design(design, tmp_path_factory.mktemp("design") / "d.json").read_text()


@pytest.fixture
def sd2_design_document(sd2_design_text) -> dict:
    """:func:`sd2_design_text` read as JSON (a fresh copy for each test)."""
    return json.loads(sd2_design_text)
