"""The valve interlocks and the divergence detector (issue 18, finding 1).

A run the real table would stop must stop in the virtual lab: a valve
command that chatters between its limits (saturated most of the time, but
never 0.25 s without a break), a valve driven above its rated current, and a
command whose high-frequency content grows (the signature of an unstable
loop).  The thresholds are :class:`~impedance_mil.lab.setup.SafetyLimits`
fields; ``docs/limits.md`` says how their defaults were chosen.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from impedance_mil.lab.kernels import hydraulic_command
from impedance_mil.lab.loop import VirtualTable, simulate, simulate_interface
from impedance_mil.lab.setup import SafetyLimits
from impedance_mil.lab.structures import HELD_STATE, Measurements
from impedance_mil.lab.trips import TripCause
from impedance_mil.plant.nonlinear import NonlinearTable

from .conftest import report_parameters

T = 0.0005  # the report's loop time [s]
#: Only the rule under test: every other valve rule out of the way.
OTHERS_OFF = dict(valve_saturation_time=1e9, valve_duty=1.0, valve_current=1e9, command_slew=1e12)


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _chatter(n: int, amplitude: float = 2.9) -> np.ndarray:
    # A position command +A, -A, 0, -A, +A, 0 repeated (zero mean, so the table stays put):
    # the valve sits at +-10 V two loops in three and flips sign, but never stays 0.25 s
    # at its limit -- the audit's diverging run (75 % of samples at the limit, 258 sign
    # flips a second).
    return amplitude * np.resize([1.0, -1.0, 0.0, -1.0, 1.0, 0.0], n)


def test_running_averages_follow_the_closed_form(table):
    # A valve saturated in every loop: the exponentially weighted duty after N loops is
    # 1 - (1 - T/window)^N exactly, and the mean-square current (K_v u_v,max)^2 times the
    # same factor (closed form of the recursion; K_v = 3 mA/V, u_v,max = 10 V: 30 mA).
    limits = SafetyLimits().kernel_values(table)
    held = np.zeros(1, HELD_STATE)
    pa = table.parameter_array()
    still = Measurements(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    n = 300
    for _ in range(n):
        hydraulic_command(pa, limits, held, np.zeros(1), still, 10.0)  # 10 in of error: saturated
    factor = 1.0 - (1.0 - T / limits.interlock_window) ** n
    i_sat = table.Kv * table.valve_command_limit
    assert held["duty"][0] == pytest.approx(factor, rel=1e-12)
    assert held["current_sq"][0] == pytest.approx(i_sat**2 * factor, rel=1e-12)
    # Constant command: the slew average holds only the first loop's jump (0 -> 10 V), decayed
    # over the n - 1 loops since: J w (1 - w)^(n - 1) with w = T/window.
    w = T / limits.interlock_window
    first_jump = (table.valve_command_limit / T) ** 2
    assert held["slew_sq"][0] == pytest.approx(first_jump * w * (1.0 - w) ** (n - 1), rel=1e-9)


def test_chattering_valve_passes_the_continuous_rule_but_trips_on_duty(table):
    # The audit's hole: the 0.25 s rule alone lets a chattering valve run forever.
    u = _chatter(4000)
    alone = simulate(table, command=u, limits=SafetyLimits(**OTHERS_OFF | {"valve_saturation_time": 0.25}))
    assert alone.trip is None
    r = simulate(table, command=u, limits=SafetyLimits(**OTHERS_OFF | {"valve_duty": 0.5}))
    assert r.trip.cause is TripCause.VALVE_DUTY and r.trip.limit == "valve_duty"
    assert 0.5 < r.trip.value <= 1.0
    # Saturated two loops in three, the duty (2/3) (1 - (1 - T/0.25)^N) passes 0.5 after
    # N = ln(1/4) / ln(1 - T/0.25) = 692 loops (0.346 s), give or take the pattern's phase.
    assert np.mean(np.abs(r.u_v) >= 10.0) == pytest.approx(2.0 / 3.0, abs=0.01)
    loops = math.log(0.25) / math.log(1.0 - T / 0.25)
    assert r.trip.time_s == pytest.approx(loops * T, abs=8 * T)
    assert r.n_samples > 0  # the data up to the trip are kept


def test_current_above_rating_trips(table):
    # A steady saturating command: 30 mA in the valve; with a 10 mA rms rating the rule
    # trips when 900 (1 - (1 - T/0.25)^N) passes 100 mA^2 (N = 59 loops, 29.5 ms).
    r = simulate(
        table,
        command=np.full(4000, 2.9),
        # (the saturated valve builds the stall pressure within 6 ms: the force rule set aside)
        limits=SafetyLimits(**OTHERS_OFF | {"valve_current": 10.0, "actuator_force": 1e9}),
    )
    assert r.trip.cause is TripCause.VALVE_CURRENT and r.trip.unit == "mA"
    assert r.trip.value > 10.0
    loops = math.ceil(math.log(1 - 100.0 / 900.0) / math.log(1.0 - T / 0.25))
    assert r.trip.time_s == pytest.approx(loops * T, abs=3 * T)
    # The default rating is the table's rated current (25 mA, report Section 4): a run
    # saturated without a break trips the 0.25 s rule before the rms current gets there.
    assert SafetyLimits().kernel_values(table).valve_current == table.spool_limit == 25.0


def test_growing_high_frequency_command_trips_the_divergence_detector(table):
    # Default threshold: the rms slew of a full-scale (10 V) valve command at 50 Hz.
    default = SafetyLimits().kernel_values(table).command_slew
    assert default == pytest.approx(2 * math.pi * 50.0 * 10.0 / math.sqrt(2.0), rel=1e-15)
    u = _chatter(4000)
    r = simulate(table, command=u, limits=SafetyLimits(**OTHERS_OFF | {"command_slew": 2000.0}))
    assert r.trip.cause is TripCause.COMMAND_OSCILLATION and r.trip.unit == "V/s"
    assert r.trip.value > 2000.0
    # The Python plant-interface path (where hardware could stand) trips at the same loop.
    limits = SafetyLimits(**OTHERS_OFF | {"command_slew": 2000.0})
    slow = simulate_interface(VirtualTable(table, limits=limits), command=u)
    assert slow.trip == r.trip and slow.n_samples == r.n_samples


def test_a_smooth_command_trips_nothing(table):
    # A 2 Hz, 1 in sine (within stroke, velocity and the valve's flow): every rule at its default.
    u = 1.0 * np.sin(2 * np.pi * 2.0 * np.arange(8000) * T)
    assert simulate(table, command=u).trip is None


@pytest.mark.parametrize(
    "key, value",
    [
        ("valve_duty", 0.0),
        ("valve_duty", 1.5),
        ("valve_current", -1.0),
        ("command_slew", 0.0),
        ("interlock_window", math.nan),
    ],
)
def test_bad_thresholds_are_refused_naming_the_key(key, value):
    with pytest.raises(ValueError, match=f"limits.{key}"):
        SafetyLimits(**{key: value})
