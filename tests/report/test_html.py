"""The run page from plain arrays: content, isolator loop, self-containment (no browser needed)."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

from impedance_mil.report.html import RunView, flatten, html_page, render_run_html


def _channels(n=4000, dt=0.0005):
    t = np.arange(n) * dt
    a_g = np.full(n, 10.0)  # constant 10 in/s^2: x_g = 5 t^2 exactly
    return {"t": t, "a_g": a_g, "z": a_g.copy(), "z_vs": 0.5 * a_g, "x": 5.0 * t**2 + 0.1, "w": 3.0 * a_g}


def test_isolator_loop_is_w_minus_m_vs_z_against_x_minus_x_g():
    # Report Section 9.3: F_exp = w - m_vs z_exp and D_exp = x_exp - x_g.
    view = RunView.from_channels(_channels(), m_vs=2.0)
    (loop,) = view.loops
    assert loop.force == pytest.approx(np.full(4000, 3.0 * 10.0 - 2.0 * 10.0))
    assert loop.displacement == pytest.approx(np.full(4000, 0.1), abs=1e-12)
    assert view.target_accel is not None and view.target_accel[0] == 5.0
    assert RunView.from_channels(_channels()).loops == ()
    model = RunView.from_channels(_channels(), m_vs=2.0, model_loop=([0.0, 1.0], [0.0, 5.0])).loops
    assert [loop.role for loop in model] == ["table", "model"] and list(model[1].force) == [0.0, 5.0]


def test_target_falls_back_to_the_input_in_tracking():
    channels = _channels()
    channels["z_vs"] = np.zeros(4000)
    assert np.array_equal(RunView.from_channels(channels).target_accel, channels["a_g"])


class _Trip:
    limit, time_s = "stroke", 1.25


class _Result:
    channels = _channels()
    config = {"motion": "GM1", "table": {"Kp": 0.001}}
    trip = _Trip()
    mode = "mil"


def test_page_is_self_contained_and_shows_status_metrics_config():
    view = RunView.from_result(_Result(), metrics={"nrms_error": 0.0312345}, m_vs=2.0)
    page = render_run_html(view)
    assert page.startswith("<!DOCTYPE html>") and "<script" not in page
    assert not re.search(r'(src|href)="(?!data:|#)', page)  # only data: URIs and anchors
    assert page.count('src="data:image/png;base64,') == 3  # histories, spectra, loop
    assert "limit &#x27;stroke&#x27; tripped at t = 1.2500 s" in page
    assert "0.03123" in page and "table.Kp" in page


def test_html_escapes_text():
    page = html_page("<b>x</b>", ["<p>ok</p>"], subtitle="a & b")
    assert "&lt;b&gt;x&lt;/b&gt;" in page and "a &amp; b" in page


def test_flatten_nested_configuration():
    assert flatten({"a": {"b": 1, "c": {"d": 2}}, "e": list(range(20))}) == {
        "a.b": 1,
        "a.c.d": 2,
        "e": "[20 values]",
    }


def test_run_title_names_the_motion_not_its_description_dict():
    # The lab stores config["motion"] as a mapping (name, source, time step ...); the page title
    # must show the record's name, not the mapping's repr.
    t = np.arange(200) * 0.0005
    channels = {
        "t": t,
        "z": np.sin(t),
        "z_vs": np.sin(t),
        "a_g": np.sin(t),
        "x": 0 * t,
        "w": 0 * t,
        "u_w": 0 * t,
    }
    result = SimpleNamespace(
        mode="mil",
        channels=channels,
        trip=None,
        loop_time=0.0005,
        config={"motion": {"name": "El Centro (RSN 6)", "pga_g": 0.6}},
    )
    view = RunView.from_result(result)
    assert view.title == "mil run: El Centro (RSN 6)"


def test_flatten_lists_of_records_row_by_row():
    rows = flatten({"sensors": [{"name": "accelerometer", "scale": 259.1}, {"scale": 2.0}], "n": [1, 2]})
    assert rows == {
        "sensors[accelerometer].name": "accelerometer",
        "sensors[accelerometer].scale": 259.1,
        "sensors[1].scale": 2.0,
        "n": [1, 2],
    }
