"""Reading an LTI table file (``[model]``: transfer-function, zpk or state-space; see :mod:`.lti_table`).

Every problem is one :class:`~impedance_mil.errors.ConfigError` naming the
file and key (``tbl.toml: model.H_zu: ...``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..config import quantity
from ..errors import ConfigError
from ..lazy import LazyModule
from ..lti import StateSpace
from ..systems import TransferFunction
from .capacity import TableCapacity
from .linear import DEFAULT_PADE_ORDER, MAX_PADE_ORDER
from .lti_table import (
    DERIVED_OUTPUTS,
    KINDS,
    LTI_DELAYS,
    LTI_INPUTS,
    LTI_OUTPUTS,
    SIGNAL_UNITS,
    LTITable,
    table_system,
)
from .statespace import TableStateSpace

#: scipy.linalg, imported on first use (issue 16: a command that only reads a configuration does not need it).
scipy_linalg = LazyModule("scipy.linalg")

_COMMON_KEYS = ("kind", "loop_time", "delay", "units", "allow_unstable", "pade_order")
_PATH_KEYS = tuple(f"H_{o}{i}" for o in LTI_OUTPUTS for i in LTI_INPUTS)
_SS_KEYS = ("A", "B", "C", "D", "inputs", "outputs")


def lti_table_from_mapping(section: Any, where: str = "", capacity: TableCapacity | None = None) -> LTITable:
    """An :class:`LTITable` from the ``[model]`` mapping of a file (keys named ``{where}model.KEY``).

    ``capacity`` is the file's ``[capacity]`` (:mod:`.capacity`; default: none stated).
    """
    key = f"{where}model."
    if not isinstance(section, Mapping):
        raise ConfigError(f"{where}model", "a [model] table", section)
    kind = section.get("kind")
    if kind not in KINDS:
        raise ConfigError(f"{key}kind", "one of " + ", ".join(KINDS), kind)
    allowed = _COMMON_KEYS + (_SS_KEYS if kind == "state-space" else _PATH_KEYS)
    unknown = sorted(set(section) - set(allowed))
    if unknown:
        raise ConfigError(f"{key}{unknown[0]}", f"one of the keys of a {kind} model: " + ", ".join(allowed))
    if "loop_time" not in section:
        raise ConfigError(f"{key}loop_time", "the controller loop time (every LTI table states it)")
    loop_time = quantity(f"{key}loop_time", section["loop_time"], "second", "nonnegative")
    delay = section.get("delay")
    if delay not in LTI_DELAYS:
        raise ConfigError(f"{key}delay", "one of " + ", ".join(LTI_DELAYS), delay)
    allow = section.get("allow_unstable", False)
    if not isinstance(allow, bool):
        raise ConfigError(f"{key}allow_unstable", "true or false", allow)
    order = section.get("pade_order", DEFAULT_PADE_ORDER)
    if isinstance(order, bool) or not isinstance(order, int):
        raise ConfigError(f"{key}pade_order", f"an integer from 1 to {MAX_PADE_ORDER}", order)
    units = section.get("units")
    if not isinstance(units, Mapping):
        raise ConfigError(
            f"{key}units", "a table of the signals' units, e.g. { z = 'in/s**2', u = 'in', w = 'lbf' }", units
        )
    if kind == "state-space":
        model = _state_space_model(section, units, key)
    else:
        model = _path_model(section, units, key, kind)
    try:
        return LTITable(model, loop_time, delay, kind, order, allow, capacity or TableCapacity())
    except ConfigError as exc:
        raise ConfigError(f"{key}{exc.key}", exc.expected, exc.got) from None


def _factors(units: Mapping[str, Any], signals, key: str) -> dict[str, float]:
    """Internal units per file unit of each signal used (``units`` must name each, and only known ones)."""
    unknown = sorted(set(units) - set(SIGNAL_UNITS))
    if unknown:
        raise ConfigError(f"{key}units.{unknown[0]}", "a signal: " + ", ".join(SIGNAL_UNITS))
    out = {}
    for name in signals:
        if name not in units:
            raise ConfigError(f"{key}units.{name}", f"the unit of {name} (a {SIGNAL_UNITS[name]})")
        unit = units[name]
        if not isinstance(unit, str) or not unit.strip():
            raise ConfigError(f"{key}units.{name}", f"a unit of {SIGNAL_UNITS[name]}", unit)
        out[name] = quantity(f"{key}units.{name}", f"1 {unit}", SIGNAL_UNITS[name])
    return out


def _numbers(value: Any, key: str, what: str) -> np.ndarray:
    """A flat list of finite real numbers (not booleans)."""
    if not isinstance(value, list) or not value:
        raise ConfigError(key, f"{what}: a non-empty list of numbers", value)
    if any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value):
        raise ConfigError(key, f"{what}: numbers only", value)
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ConfigError(key, f"{what}: finite numbers (no NaN or inf)", value)
    return arr


def _polynomial(value: Any, key: str) -> np.ndarray:
    arr = _numbers(value, key, "coefficients in descending powers of s")
    if not np.any(arr):
        raise ConfigError(key, "coefficients that are not all zero", value)
    return arr


def _roots(value: Any, key: str) -> np.ndarray:
    """Roots [rad/s]: numbers or ``[re, im]`` pairs; each complex root with its conjugate."""
    if not isinstance(value, list):
        raise ConfigError(key, "a list of roots: numbers, or [re, im] pairs for complex ones", value)
    roots = []
    for item in value:
        if isinstance(item, list):
            if len(item) != 2:
                raise ConfigError(key, "a complex root as a pair [re, im]", item)
            re, im = _numbers(item, key, "a complex root as [re, im]")
            roots.append(complex(float(re), float(im)))
        else:
            roots.append(complex(_numbers([item], key, "a real root")[0]))
    remaining = [r for r in roots if r.imag != 0]
    while remaining:
        r = remaining.pop(0)
        mate = next((k for k, q in enumerate(remaining) if q == r.conjugate()), None)
        if mate is None:
            raise ConfigError(
                key,
                "complex roots in conjugate pairs ([re, im] and [re, -im])",
                f"[{r.real:g}, {r.imag:g}] alone",
            )
        remaining.pop(mate)
    return np.array(roots, dtype=complex)


def _path(entry: Any, key: str, kind: str, scale: float) -> TransferFunction:
    """One path of a transfer-function or zpk model, times ``scale`` (internal units), proper."""
    names = ("num", "den") if kind == "transfer-function" else ("zeros", "poles", "gain")
    if not isinstance(entry, Mapping) or set(entry) != set(names):
        raise ConfigError(key, "{ " + ", ".join(f"{n} = ..." for n in names) + " }", entry)
    if kind == "transfer-function":
        H = TransferFunction(
            scale * _polynomial(entry["num"], f"{key}.num"), _polynomial(entry["den"], f"{key}.den")
        )
    else:
        gain = _numbers([entry["gain"]], f"{key}.gain", "a real gain")[0]
        if gain == 0:
            raise ConfigError(f"{key}.gain", "a non-zero gain", entry["gain"])
        H = TransferFunction.from_zpk(
            _roots(entry["zeros"], f"{key}.zeros"), _roots(entry["poles"], f"{key}.poles"), scale * gain
        )
    if not H.is_proper:
        raise ConfigError(
            key,
            "a proper transfer function (no more zeros than poles)",
            f"relative degree {H.relative_degree}",
        )
    return H


def _origin_zeros(H: TransferFunction) -> int:
    """Number of exact zeros at the origin (trailing zero coefficients of the numerator)."""
    nz = np.flatnonzero(H.num)
    return H.num.size - 1 - int(nz[-1]) if nz.size else 0


def _path_model(section: Mapping[str, Any], units: Mapping[str, Any], key: str, kind: str) -> TableStateSpace:
    """The model of a transfer-function or zpk file, realized input by input."""
    given = [(k[2:-1], k[-1]) for k in _PATH_KEYS if k in section]
    if ("z", "u") not in given:
        raise ConfigError(f"{key}H_zu", "the path z/u (every table has it)")
    inputs = [i for i in LTI_INPUTS if any(g[1] == i for g in given)]
    factors = _factors(units, sorted({o for o, _ in given} | set(inputs) | {"z"}), key)
    paths = {
        (o, i): _path(section[f"H_{o}{i}"], f"{key}H_{o}{i}", kind, factors[o] / factors[i]) for o, i in given
    }
    for i in inputs:
        if ("z", i) not in paths:
            raise ConfigError(f"{key}H_z{i}", f"the path z/{i} (the table has other paths from {i})")
    outputs = ["z"] + [o for o in LTI_OUTPUTS[1:] if any((o, i) in paths for i in inputs)]
    for out, count in DERIVED_OUTPUTS.items():
        if out not in outputs and all(_origin_zeros(paths[("z", i)]) >= count for i in inputs):
            for i in inputs:
                z = paths[("z", i)]
                paths[(out, i)] = TransferFunction(z.num[: z.num.size - count], z.den)
            outputs.append(out)
    outputs = [o for o in LTI_OUTPUTS if o in outputs]
    for o in outputs:
        for i in inputs:
            if (o, i) not in paths:
                raise ConfigError(f"{key}H_{o}{i}", f"given with the other paths of {o} (or none of {o})")
    columns = [_column(i, [paths[(o, i)] for o in outputs]) for i in inputs]
    A = scipy_linalg.block_diag(*[c.A for c in columns]) if columns else np.zeros((0, 0))
    B = scipy_linalg.block_diag(*[c.B for c in columns])
    C = np.hstack([c.C for c in columns])
    D = np.hstack([c.D for c in columns])
    states = tuple(s for c in columns for s in c.states)
    sys = StateSpace(A, B, C, D, 0.0, tuple(inputs), tuple(outputs), states)
    return table_system(sys)


def _column(input: str, paths: list[TransferFunction]) -> StateSpace:
    """Controllable-canonical realization of the paths of one input over their common denominator.

    The common denominator is the product of the distinct denominators (equal
    ones, to 1e-12 relative, counted once), so shared poles are one set of
    states; exact zeros of the numerators stay exact in ``C``.
    """
    distinct: list[np.ndarray] = []
    for H in paths:
        if not any(d.size == H.den.size and np.allclose(d, H.den, rtol=1e-12, atol=0) for d in distinct):
            distinct.append(H.den)
    den = np.ones(1)
    for d in distinct:
        den = np.polymul(den, d)
    n = den.size - 1
    rows, feed = [], []
    for H in paths:
        own = next(
            k
            for k, d in enumerate(distinct)
            if d.size == H.den.size and np.allclose(d, H.den, rtol=1e-12, atol=0)
        )
        num = H.num
        for k, d in enumerate(distinct):
            if k != own:
                num = np.polymul(num, d)
        num = np.pad(num, (n + 1 - num.size, 0))
        feed.append(num[0])
        rows.append(num[1:] - num[0] * den[1:])
    A = np.zeros((n, n))
    if n:
        A[0, :] = -den[1:]
        A[1:, :-1] = np.eye(n - 1)
    B = np.zeros((n, 1))
    if n:
        B[0, 0] = 1.0
    states = tuple(f"{input}_{k + 1}" for k in range(n))
    return StateSpace(
        A, B, np.array(rows).reshape(len(paths), n), np.array(feed).reshape(-1, 1), 0.0, (input,), (), states
    )


def _matrix(
    section: Mapping[str, Any], name: str, key: str, shape: tuple[int | None, int | None]
) -> np.ndarray:
    """A matrix (list of rows of numbers) of the given shape (None: any)."""
    value = section[name]
    if not isinstance(value, list) or not all(isinstance(r, list) for r in value):
        raise ConfigError(f"{key}{name}", "a matrix: a list of rows, e.g. [[1.0, 0.0], [0.0, 1.0]]", value)
    rows = [_numbers(r, f"{key}{name}", "a row of numbers") for r in value] if value else []
    widths = {r.size for r in rows}
    if len(widths) > 1:
        raise ConfigError(f"{key}{name}", "rows of equal length", f"lengths {sorted(widths)}")
    M = np.array(rows, dtype=float).reshape(len(rows), widths.pop() if widths else 0)
    want = tuple(s if s is not None else M.shape[k] for k, s in enumerate(shape))
    if M.shape != want:
        raise ConfigError(f"{key}{name}", f"a {want[0]} x {want[1]} matrix", f"{M.shape[0]} x {M.shape[1]}")
    return M


def _names(section: Mapping[str, Any], name: str, key: str, known, first: str) -> list[str]:
    value = section.get(name)
    if (
        not isinstance(value, list)
        or not all(isinstance(v, str) and v in known for v in value)
        or len(set(value)) != len(value)
        or first not in value
    ):
        raise ConfigError(
            f"{key}{name}", f"a list of distinct names of {', '.join(known)} with {first!r}", value
        )
    return list(value)


def _state_space_model(section: Mapping[str, Any], units: Mapping[str, Any], key: str) -> TableStateSpace:
    """The model of a state-space file: ``A, B, C, D`` with named inputs and outputs, scaled to internal units."""
    for name in ("A", "B", "C"):
        if name not in section:
            raise ConfigError(f"{key}{name}", "a matrix of the state space (A, B, C; D optional)")
    inputs = _names(section, "inputs", key, LTI_INPUTS, "u")
    outputs = _names(section, "outputs", key, LTI_OUTPUTS, "z")
    A = _matrix(section, "A", key, (None, None))
    n = A.shape[0]
    if A.shape[1] != n:
        raise ConfigError(f"{key}A", "a square matrix", f"{A.shape[0]} x {A.shape[1]}")
    B = _matrix(section, "B", key, (n, len(inputs)))
    C = _matrix(section, "C", key, (len(outputs), n))
    D = (
        _matrix(section, "D", key, (len(outputs), len(inputs)))
        if "D" in section
        else np.zeros((len(outputs), len(inputs)))
    )
    factors = _factors(units, outputs + inputs, key)
    fin = np.array([factors[i] for i in inputs])
    fout = np.array([factors[o] for o in outputs])
    sys = StateSpace(
        A, B / fin, fout[:, None] * C, fout[:, None] * D / fin, 0.0, tuple(inputs), tuple(outputs)
    )
    return table_system(sys)
