"""The ten-line VS type of CONTRIBUTING.md is a working type: it runs, linearizes and renders."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from impedance_mil.implement import discretize
from impedance_mil.implement.c import render_c
from impedance_mil.implement.safety import CommandLimits
from impedance_mil.systems import TransferFunction

CONTRIBUTING = Path(__file__).resolve().parents[2] / "CONTRIBUTING.md"


def test_the_documented_type_works():
    block = re.search(r"## Add a virtual-system type.*?```python\n(.*?)```", CONTRIBUTING.read_text(), re.S)
    namespace: dict = {}
    exec(compile(block.group(1), "CONTRIBUTING.md", "exec"), namespace)  # noqa: S102 - our own docs
    vs = namespace["TYPE"].build_preset("VD1")
    # closed form of the linear spring-damper: H_zw = s^2/(m s^2 + c s + k)
    f = np.array([0.5, 2.0, 10.0])
    ref = TransferFunction([1.0, 0.0, 0.0], [5.2, 60.0, 900.0]).frequency_response(f)
    np.testing.assert_allclose(vs.linear_part().H_zw.frequency_response(f), ref, rtol=1e-12)
    r = vs.simulate(np.full(2000, 100.0), 0.0, 0.0005)
    assert np.isfinite(r.z_vs).all() and abs(r.displacement[-1]) > 0
    ctrl = discretize(
        TransferFunction([1.0, 30.0, 200.0], [1.0, 0.0, 0.0]),
        TransferFunction([-0.01], [1.0, 500.0]),
        0.0005,
        fc_hz=80.0,
    )
    limits = CommandLimits(stroke_in=3.2, max_rate_in_s=47.6, accel_limit_in_s2=1.5e4, force_limit_lbf=6.3e4)
    assert "vd_mil_step" in render_c(ctrl, "single", "vd", vs=vs, limits=limits).files["vd.c"]
