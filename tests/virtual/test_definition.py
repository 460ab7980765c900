"""VS definitions: what is refused when a definition is made, and what is derived from it.

A bad definition is refused when it is loaded, in one line naming the
definition and the symbol (issue 11, "Bad input").
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from impedance_mil.virtual import (
    Parameter,
    VSDefinition,
    VSDefinitionError,
    compiled,
    load_type_file,
    presets,
)
from impedance_mil.virtual.expressions import python_dialect, render
from impedance_mil.virtual.structure import linear_structure

#: A small valid definition (a linear spring-damper), varied by the tests below.
GOOD = dict(
    kind="T1",
    title="test",
    source="test",
    parameters=(
        Parameter("m_vs", "force_pound * second**2 / inch", "mass"),
        Parameter("k", "force_pound / inch", "stiffness"),
    ),
    states=("x", "v"),
    state_units=("inch", "inch / second"),
    intermediates=(("F", "k*x"),),
    rates={"x": "v", "v": "(w - F)/m_vs - a_g"},
    outputs={"z_vs": "(w - F)/m_vs", "force": "F"},
    kinematics=("x", "v"),
    reference={"m_vs": 1.0, "k": 100.0},
)


def _refused(**changes) -> str:
    with pytest.raises(VSDefinitionError) as exc:
        VSDefinition(**{**GOOD, **changes})
    text = str(exc.value)
    assert "\n" not in text and text.startswith("VS definition T1: ")
    assert isinstance(exc.value, ValueError)
    return text


def test_the_good_definition_is_accepted_and_runs():
    d = VSDefinition(**GOOD)
    assert d.kernel_constants == ("m_vs", "k")
    assert linear_structure(d).states == ("x", "v")
    assert compiled(d).n_outputs == 4


def test_a_name_used_but_not_declared_is_refused():
    assert "c: expected a declared name (used in rates.v" in _refused(
        rates={"x": "v", "v": "(w - F - c*v)/m_vs - a_g"}
    )


def test_a_state_used_but_not_declared_is_refused():
    text = _refused(intermediates=(("F", "k*x + 3.0*y"),))
    assert "y:" in text and "intermediates.F" in text


def test_a_missing_parameter_value_is_refused():
    assert "k: expected a reference value" in _refused(reference={"m_vs": 1.0})


@pytest.mark.parametrize(
    "changes,symbol",
    [
        (dict(intermediates=(("F", "k*x*1e999"),)), "intermediates.F"),  # literal overflow
        (dict(outputs={"z_vs": "(w - F)/(m_vs - 1.0)", "force": "F"}), "z_vs"),  # 1/0 at the reference
        (dict(rates={"x": "v", "v": "(w - F)/m_vs - a_g + sqrt(k - 200.0)"}), "v"),  # sqrt of a negative
    ],
)
def test_a_non_finite_expression_is_refused(changes, symbol):
    text = _refused(**changes)
    assert symbol in text and "finite" in text


@pytest.mark.parametrize(
    "changes,fragment",
    [
        (dict(rates={"x": "v"}), "v: expected a rate for every declared state"),
        (dict(rates={"x": "v", "v": "a_g", "q": "0.0"}), "rates.q"),
        (dict(outputs={"z_vs": "(w - F)/m_vs"}), "outputs.force"),
        (dict(intermediates=(("w", "k*x"),)), "w: expected an identifier that is not reserved"),
        (dict(intermediates=(("F", "k*x**2"),)), "arithmetic"),
        (dict(intermediates=(("F", "log(x)"),)), "functions"),
        (dict(parameters=GOOD["parameters"][1:], reference={"k": 1.0}), "m_vs"),
    ],
)
def test_structural_errors_name_the_symbol(changes, fragment):
    assert fragment in _refused(**changes)


def test_a_nonlinear_term_outside_the_nonlinear_inputs_is_refused():
    d = VSDefinition(**{**GOOD, "intermediates": (("F", "k*x*abs(x)"),)})
    with pytest.raises(VSDefinitionError, match="nonlinear_inputs"):
        linear_structure(d)


def test_a_bad_type_file_is_one_line(tmp_path):
    path = tmp_path / "bad_type.py"
    path.write_text(
        "from impedance_mil.virtual import Parameter, VSDefinition\n"
        "DEFINITION = VSDefinition(kind='B', title='b', source='b', "
        "parameters=(Parameter('m_vs', 'force_pound * second**2 / inch', 'mass'),), states=('x', 'v'), "
        "state_units=('inch', 'inch/second'), rates={'x': 'v', 'v': '-k*x/m_vs - a_g'}, "
        "outputs={'z_vs': '0.0', 'force': '0.0'}, kinematics=('x', 'v'), reference={'m_vs': 1.0})\n"
    )
    with pytest.raises(VSDefinitionError) as exc:
        load_type_file(path)
    assert str(exc.value).startswith("VS definition B: k") and "\n" not in str(exc.value)


def test_renderings_keep_the_order_of_operations():
    # "a - b - c" and "a - (b - c)" must stay distinct in every target (IEEE rounding).
    for text in ("a - b - c", "a - (b - c)", "a/b/c", "a/(b*c)", "-a*b", "pow(abs(a), b)*c"):
        out = render(text, python_dialect(lambda n: n))
        env = {"a": 0.1, "b": 0.7, "c": 0.3, "_sign": np.sign, "math": math}
        assert eval(out, env) == eval(text.replace("pow", "math.pow"), env)  # noqa: S307


def test_builtin_definitions_are_equal_to_themselves_only():
    a, b = presets.get("SD2"), presets.get("SD2")
    assert a == b and hash(a) == hash(b)
    assert a != a.replace(k_s=a.k_s * 1.01)
    assert presets.get("FP2").definition.fingerprint != presets.get("LR2").definition.fingerprint
    assert dataclasses.is_dataclass(a.definition)
