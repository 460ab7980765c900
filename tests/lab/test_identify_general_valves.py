"""The multisine identification of Section 4.5.3 on a table with a first-order or a complex-pair valve.

Before, ``identify_table`` read two valve poles of every table, and ``imil frf`` on a
first-order-valve table stopped with an IndexError traceback.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.experiments import run_frf
from impedance_mil.lab.identification import _start, identify_table
from impedance_mil.plant import TableParameters

#: The general table of tests/cli/test_table_cli.py: a 24.6 ms first-order valve (the value
#: quoted in issue 13), platen damping and a grounded spring, f_oil 27 Hz.
FIRST_ORDER = Path(__file__).parents[1] / "data" / "first_order_table.toml"


@pytest.fixture(scope="module")
def first_order():
    return FIRST_ORDER


def test_imil_frf_identifies_a_first_order_valve_table(first_order, imil, tmp_path):
    # The nonlinear virtual table (friction, the flow's square root) against its own linear
    # model: f_oil measured 26.84 Hz against the file's 27 (0.6 %), the misfit 0.056.
    res = imil("frf", "--table", first_order, "-o", tmp_path / "f.h5", "--json")
    assert res.returncode == 0, res.stderr
    doc = json.loads(res.stdout)
    assert doc["f_oil_hz"] == pytest.approx(27.0, rel=0.015)
    assert doc["identification_error"] < 0.08


def test_the_valve_parameters_of_each_kind_are_the_identifiable_ones(first_order):
    p = TableParameters.from_toml(first_order)
    assert set(_start(p)) == {"f_oil_hz", "zeta_oil", "d", "valve_time_constant"}
    pair = TableParameters.report_default().replace(
        valve="second-order", valve_poles_hz=(), valve_frequency_hz=60.0, valve_damping=0.7
    )
    assert set(_start(pair)) == {"f_oil_hz", "zeta_oil", "d", "valve_frequency_hz", "valve_damping"}
    assert "valve_pole_2_hz" in _start(TableParameters.report_default())


def test_a_first_order_valve_time_constant_is_recovered_from_a_noise_free_linear_frf(first_order):
    # Fit the linear model to the FRF of itself with T started 30 % off: it returns to 24.6 ms.
    p = TableParameters.from_toml(first_order)
    exp = run_frf(p, identify=False, seed=0)
    measured = replace(exp.frf["z"], response=exp.model["z"], std=None)  # the model's own response
    fit = identify_table(
        measured,
        p.replace(valve_time_constant=0.032),
        free=("valve_time_constant",),
        f_range_hz=(0.25, 100.0),
    )
    assert fit.parameters.valve_time_constant == pytest.approx(0.0246, rel=1e-4)


def test_a_two_pole_parameter_of_a_first_order_table_is_refused_naming_free(first_order):
    p = TableParameters.from_toml(first_order)
    exp = run_frf(p, identify=False, seed=0)
    with pytest.raises(ConfigError, match="identify.free"):
        identify_table(exp.frf["z"], p, free=("valve_pole_1_hz",))
    assert np.isfinite(exp.frf["z"].response).all()
