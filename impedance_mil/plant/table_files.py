"""Table files: reading either kind (:func:`read_table_file`), and writing identified tables.

A table file is either physical (``[table]`` keys, or the keys at the top
level: :class:`~impedance_mil.plant.parameters.TableParameters`) or an LTI
table (a ``[model]`` section: :class:`~impedance_mil.plant.lti_table.LTITable`).
:func:`read_table_file` reads either; :data:`TableDefinition` is the union.

Writing:

* :func:`physical_table_toml`: a physical table file (the keys of
  :data:`impedance_mil.plant.parameters.FIELDS`, each value with its unit, full
  precision), read by :meth:`TableParameters.from_toml`;
* :func:`transfer_function_toml`: a transfer-function table in the layout of
  issue 13 (``[model] kind = "transfer-function"``, ``H_zu = { num, den }`` in
  descending powers of s [rad/s], ``units``, ``delay = "included"``,
  ``loop_time``), read back by :func:`read_table_file`.

Both start with comment lines saying where the values came from.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..config import read_toml
from ..errors import ConfigError
from ..systems import CANCEL_RTOL, TransferFunction
from .capacity import TableCapacity
from .frf_table import KIND as FRF_KIND
from .lti_reader import lti_table_from_mapping
from .lti_table import LTITable
from .parameters import FIELDS, TableParameters, merge_overrides, table_mapping
from .table_kind import LTI_FILE_SECTIONS as LTI_FILE_SECTIONS  # re-exported, as the two below
from .table_kind import is_lti_table_data
from .table_kind import is_lti_table_file as is_lti_table_file

if TYPE_CHECKING:  # the fits' type only (a writer's argument): fitting is not reading
    from .rational import RationalFit

#: What a table file holds: the physical parameters, or a linear model.
TableDefinition = TableParameters | LTITable


def read_table_file(path: str | Path, overrides: Mapping[str, Any] | None = None) -> TableDefinition:
    """The table of a file: :class:`TableParameters` for a physical file, :class:`LTITable` for ``[model]``.

    ``overrides`` (``--set``) apply to a physical table only.

    Raises
    ------
    ConfigError
        A key of the file (named), or overrides given for an LTI table
        (``--set``: it has no physical keys).
    DataFileError
        The file is missing or not TOML.
    """
    path = Path(path)
    data = read_toml(path)
    if not is_lti_table_data(data):
        return TableParameters.from_mapping(merge_overrides(table_mapping(data, path), overrides or {}))
    if overrides:
        raise ConfigError(
            "--set",
            f"no overrides for the LTI table {path.name} ([model]: it has no physical keys)",
            ", ".join(overrides),
        )
    where = f"{path.name}: "
    model = data["model"]
    if isinstance(model, Mapping) and model.get("kind") == FRF_KIND:
        # a measurement has no model to invert or to run: it checks a design (imil design --frf)
        raise ConfigError(
            f"{where}model.kind",
            "a model (transfer-function, zpk, state-space or a physical table); "
            "a measured FRF table checks a design: imil design --table MODEL --frf FILE",
            FRF_KIND,
        )
    extra = sorted(set(data) - set(LTI_FILE_SECTIONS))
    if extra:
        raise ConfigError(f"{where}{extra[0]}", "only [model] and [capacity] sections in an LTI table file")
    capacity = TableCapacity.from_mapping(data["capacity"], where) if "capacity" in data else None
    return lti_table_from_mapping(data["model"], where, capacity)


def read_lti_table(path: str | Path) -> LTITable:
    """Read an LTI table file (:mod:`impedance_mil.plant.lti_table`); a physical file is refused naming it."""
    table = read_table_file(path)
    if not isinstance(table, LTITable):
        raise ConfigError(str(path), "an LTI table file (a [model] section)", "a physical table file")
    return table


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
    fits: Mapping[str, RationalFit],
    *,
    output: str,
    units: dict[str, str],
    loop_time: float,
    header: Sequence[str] = (),
    capacity: TableCapacity | None = None,
) -> str:
    """The text of a transfer-function table file (issue 13's layout) holding ``H_<output><input>``.

    Parameters
    ----------
    fits : mapping of str to RationalFit
        The model of each input path (``{"u": ..., "w": ...}``), s in rad/s, internal units.
    output : str
        Name of the output (``"z"``).
    units : dict
        Unit of each signal named in the polynomials (``{"z": "in/s**2", "u": "in"}``).
    loop_time : float
        Controller loop time of the test [s]; the measured response includes
        the loop's delay (``delay = "included"``).
    header : sequence of str
        Comment lines at the top of the file.
    capacity : TableCapacity, optional
        The table's capacity, written as the ``[capacity]`` section (what the
        virtual lab and the generated code's limits need beside the model).
    """
    unit_text = ", ".join(f'{k} = "{v}"' for k, v in units.items())
    return (
        _comment(header)
        + "[model]\n"
        + 'kind = "transfer-function"\n'
        + 'delay = "included"\n'
        + f'loop_time = "{loop_time!r} s"\n'
        + f"units = {{ {unit_text} }}\n"
        + "".join(
            f"H_{output}{name} = {{ num = {_array(fit.num)}, den = {_array(fit.den)} }}\n"
            for name, fit in fits.items()
        )
        + _capacity_text(capacity)
    )


def _capacity_text(capacity: TableCapacity | None) -> str:
    """The ``[capacity]`` section of ``capacity`` (internal units), or nothing."""
    stated = {} if capacity is None else capacity.stated()
    if not stated:
        return ""
    lines = ["", "[capacity]", *(f'{k} = "{v!r} {_CAPACITY_FILE_UNITS[k]}"' for k, v in stated.items())]
    return "\n".join(lines) + "\n"


#: Internal unit of each signal as written in a table file's ``units``.
_FILE_UNITS = {"u": "in", "w": "lbf", "z": "in/s**2", "x": "in", "v": "in/s", "dp": "psi"}


def _pairs(roots) -> str:
    items = [repr(float(r.real)) if r.imag == 0 else f"[{float(r.real)!r}, {float(r.imag)!r}]" for r in roots]
    return "[" + ", ".join(items) + "]"


def lti_table_toml(table: LTITable, kind: str | None = None, header: Sequence[str] = ()) -> str:
    """The text of an LTI table file holding ``table`` (internal units), read back by :func:`read_table_file`.

    Parameters
    ----------
    table : LTITable
    kind : str, optional
        ``"state-space"`` (the model's matrices), ``"transfer-function"`` or
        ``"zpk"`` (every path of the model, round-off safe); default the table's kind.
        The paths written are of the file's model (no delay added): the
        delay treatment is written as ``delay``.
    """
    kind = table.kind if kind is None else kind
    sys = table.state_space().system
    names = list(dict.fromkeys(["u", "w", *sys.outputs]))
    lines = [
        "[model]",
        f"kind = {kind!r}".replace("'", '"'),
        f'loop_time = "{table.loop_time!r} s"',
        f'delay = "{table.delay}"',
        "units = { " + ", ".join(f'{k} = "{_FILE_UNITS[k]}"' for k in names) + " }",
    ]
    if table.allow_unstable:
        lines.append("allow_unstable = true")
    if table.delay == "pade":
        lines.append(f"pade_order = {int(table.pade_order)}")
    if kind == "state-space":
        lines += [
            'inputs = ["u", "w"]',
            "outputs = [" + ", ".join(f'"{o}"' for o in sys.outputs) + "]",
            *(f"{m} = [" + ", ".join(_array(r) for r in getattr(sys, m)) + "]" for m in "ABCD"),
        ]
    else:
        for o in sys.outputs:
            for i in ("u", "w"):
                H = TransferFunction.from_lti(sys.reachable(i).channel(o, i), cancel_rtol=CANCEL_RTOL)
                if H.is_zero:
                    continue
                if kind == "transfer-function":
                    lines.append(f"H_{o}{i} = {{ num = {_array(H.num)}, den = {_array(H.den)} }}")
                else:
                    lines.append(
                        f"H_{o}{i} = {{ zeros = {_pairs(_conjugate(H.zeros()))}, "
                        f"poles = {_pairs(_conjugate(H.poles()))}, gain = {float(H.num[0])!r} }}"
                    )
    return _comment(header) + "\n".join(lines) + "\n" + _capacity_text(table.capacity)


#: Internal unit of each ``[capacity]`` key as written in a table file.
_CAPACITY_FILE_UNITS = {
    "stroke": "in",
    "velocity": "in/s",
    "force": "lbf",
    "mass": "lbf*s**2/in",
    "piston_area": "in**2",
}


def _conjugate(roots) -> list[complex]:
    """Roots with the conjugate of each complex one exactly mirrored (as a zpk file requires)."""
    out = []
    upper = [r for r in roots if r.imag > 0]
    out += [complex(r.real, 0.0) for r in roots if r.imag == 0]
    for r in upper:
        out += [r, r.conjugate()]
    return out
