"""Writing identified tables as files that ``--table`` reads back.

* :func:`physical_table_toml`: a physical table file (the keys of
  :data:`impedance_mil.plant.parameters.FIELDS`, each value with its unit, full
  precision), read by :meth:`TableParameters.from_toml`;
* :func:`transfer_function_toml`: a transfer-function table in the layout of
  issue 13 (``[model] kind = "transfer-function"``, ``H_zu = { num, den }`` in
  descending powers of s [rad/s], ``units``, ``delay = "included"``,
  ``loop_time``).  The toolkit reads such a file once LTI tables exist
  (issue 13); until then it documents the identified model.

Both start with comment lines saying where the values came from.
"""

from __future__ import annotations

from collections.abc import Sequence

from .parameters import FIELDS, TableParameters
from .rational import RationalFit


def _comment(lines: Sequence[str]) -> str:
    return "".join(f"# {line}\n" for line in lines)


def _value(value: float, unit: str) -> str:
    return f'"{value!r} {unit}"' if unit != "dimensionless" else repr(float(value))


def physical_table_toml(params: TableParameters, header: Sequence[str] = ()) -> str:
    """The text of a table file holding ``params`` (the keys of ``params.to_dict()``, each with its unit)."""
    rows = []
    for key, value in params.to_dict().items():
        if key == "valve":  # the valve kind of a general table: a word
            rows.append(f'{key} = "{value}"')
            continue
        spec = FIELDS[key]
        if spec.count > 1:
            text = "[" + ", ".join(_value(v, spec.unit) for v in value) + "]"
        else:
            text = _value(value, spec.unit)
        rows.append(f"{key} = {text}")
    return _comment(header) + "[table]\n" + "\n".join(rows) + "\n"


def _array(values) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def transfer_function_toml(
    fit: RationalFit,
    *,
    output: str,
    input: str,
    units: dict[str, str],
    loop_time: float,
    header: Sequence[str] = (),
) -> str:
    """The text of a transfer-function table file (issue 13's layout) holding ``H_<output><input>``.

    Parameters
    ----------
    fit : RationalFit
        The model, s in rad/s, internal units.
    output, input : str
        Names of the output and input (``"z"``, ``"u"``).
    units : dict
        Unit of each signal named in the polynomials (``{"z": "in/s**2", "u": "in"}``).
    loop_time : float
        Controller loop time of the test [s]; the measured response includes
        the loop's delay (``delay = "included"``).
    """
    unit_text = ", ".join(f'{k} = "{v}"' for k, v in units.items())
    return (
        _comment(header)
        + "[model]\n"
        + 'kind = "transfer-function"\n'
        + 'delay = "included"\n'
        + f'loop_time = "{loop_time!r} s"\n'
        + f"units = {{ {unit_text} }}\n"
        + f"H_{output}{input} = {{ num = {_array(fit.num)}, den = {_array(fit.den)} }}\n"
    )
