"""Calibrating a lab on ONE observation of the report, fixed in advance (issue 17, item 2).

A *protocol* file names, before any calibrating run:

* the claim calibrated on (a :data:`~impedance_mil.campaign.claims.CLAIMS` id);
* the base lab: every other dynamic at the typical value of its cited source;
* the one unknown parameter: the lab-file keys it sets, its unit, and the range
  of its cited sources (the calibration never leaves it);
* the observation as a stability bracket: a campaign kind's run (``set``), one
  setting varied (``vary``) at a value the report found stable and one it found
  unstable (footnote 22: tracking at 42 in, f_c = 100 Hz stable, 150 Hz not).

:func:`calibrate` then finds, by bisection, the smallest parameter value at
which the unstable setting goes unstable and the smallest at which the stable
one does, both judged by the claims' own rule
(:func:`~impedance_mil.campaign.claims.run_stability`), and takes the midpoint
of the interval between them: every value inside reproduces the observation,
the midpoint commits to none of its ends.  Instability is assumed to grow
with the parameter (a delay, a compliance): the protocol says so, and each
bisection checks its ends.  When no value in the source range reproduces the
observation, the calibration says so and keeps the range's end nearest to it
by the claims' own measure (where the unstable setting's high-frequency ratio is
largest); it never widens the range.

The result is a calibrated lab file (the base lab, the parameter set, and a
``[calibration]`` record naming the claim, so the reproduction page marks it
as the calibrating one) and ``calibration.json`` with every evaluation.
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from tempfile import TemporaryDirectory
from typing import Any

from ..config import quantity, read_toml
from ..errors import ConfigError
from ..fileio import atomic_directory, json_safe
from ..tomlwrite import toml_text
from .claims import CLAIMS, run_stability
from .kinds import get_kind
from .params import convert_settings, set_path

#: Kinds a calibration observation may use (runs of the virtual lab with a lab file).
OBSERVATION_KINDS = ("tracking", "mil")
#: Most bisection steps per end (the resolution stops it first).
MAX_STEPS = 20


@dataclass(frozen=True)
class CalibratedParameter:
    """The one unknown: the lab-file keys it sets, its unit, its cited range.

    Attributes
    ----------
    name : str
        What it is, in words.
    keys : tuple of str
        Dotted lab-file keys that all take the value (four load cells: four keys).
    unit : str
        The unit the value is written in (pint).
    low, high : float
        The range of the cited sources [unit].
    resolution : float
        Bisection stops when an interval is narrower [unit].
    source : str
        The citation of the range.
    """

    name: str
    keys: tuple[str, ...]
    unit: str
    low: float
    high: float
    resolution: float
    source: str


@dataclass(frozen=True)
class Observation:
    """The report's observation as a stability bracket of one varied setting.

    Attributes
    ----------
    kind : str
        Campaign kind of the runs (``tracking`` or ``mil``).
    settings : mapping
        The runs' campaign parameters (converted, internal units).
    vary : str
        The varied campaign parameter.
    stable, unstable : float
        Its value the report found stable, and the one it found unstable (internal unit).
    """

    kind: str
    settings: Mapping[str, Any]
    vary: str
    stable: float
    unstable: float


@dataclass(frozen=True)
class CalibrationProtocol:
    """A protocol file, validated (see the module docstring)."""

    path: Path
    claim: str
    base_lab: Path
    why: str
    parameter: CalibratedParameter
    observation: Observation


@dataclass(frozen=True)
class Evaluation:
    """One run of the calibration: the parameter value, the varied setting, the verdict."""

    value: float
    setting: float
    verdict: str
    hf_ratio: float | None
    trip: str | None


@dataclass(frozen=True)
class CalibrationResult:
    """What :func:`calibrate` found.

    Attributes
    ----------
    protocol : CalibrationProtocol
    value : float
        The calibrated value [parameter unit], inside the source range.
    reproduced : bool
        Whether the observation holds at ``value`` (both ends of the bracket judged as the report).
    onset_unstable, onset_stable : float or None
        Smallest value at which the unstable / the stable setting goes unstable (None: not in the range).
    evaluations : tuple of Evaluation
    note : str
        One sentence: what the calibration found.
    """

    protocol: CalibrationProtocol
    value: float
    reproduced: bool
    onset_unstable: float | None
    onset_stable: float | None
    evaluations: tuple[Evaluation, ...] = field(default=())
    note: str = ""

    def to_dict(self, relative_to: Path | None = None) -> dict[str, Any]:
        """JSON-safe record; file paths relative to ``relative_to`` when given (the output folder)."""
        p = self.protocol

        def where(path: Path) -> str:
            return (
                str(path)
                if relative_to is None
                else Path(os.path.relpath(path, relative_to.resolve())).as_posix()
            )

        return json_safe(
            {
                "protocol": where(p.path),
                "claim": p.claim,
                "base_lab": where(p.base_lab),
                "why": p.why,
                "parameter": {**asdict(p.parameter), "keys": list(p.parameter.keys)},
                "observation": {
                    "kind": p.observation.kind,
                    "settings": dict(p.observation.settings),
                    "vary": p.observation.vary,
                    "stable": p.observation.stable,
                    "unstable": p.observation.unstable,
                },
                "value": self.value,
                "unit": p.parameter.unit,
                "reproduced": self.reproduced,
                "onset_unstable": self.onset_unstable,
                "onset_stable": self.onset_stable,
                "note": self.note,
                "evaluations": [asdict(e) for e in self.evaluations],
            }
        )


def load_protocol(path: str | Path) -> CalibrationProtocol:
    """Read and validate a protocol file; errors name the file and key (:class:`ConfigError`)."""
    path = Path(path)
    raw = read_toml(path)
    where = f"{path.name}: "
    unknown = sorted(set(raw) - {"calibration", "parameter", "observation"})
    if unknown:
        raise ConfigError(f"{where}[{unknown[0]}]", "the sections [calibration], [parameter], [observation]")
    head = _section(raw, "calibration", where)
    claim = _text(head, "claim", where + "calibration.")
    if claim not in {c.id for c in CLAIMS}:
        raise ConfigError(f"{where}calibration.claim", "the id of a claim of the reproduction suite", claim)
    base_lab = (path.parent / _text(head, "lab", where + "calibration.")).resolve()
    if not base_lab.is_file():
        raise ConfigError(
            f"{where}calibration.lab", "an existing lab file (relative to the protocol)", str(base_lab)
        )
    return CalibrationProtocol(
        path.resolve(),
        claim,
        base_lab,
        str(head.get("why", "")),
        _parameter(_section(raw, "parameter", where), where + "parameter."),
        _observation(_section(raw, "observation", where), where + "observation."),
    )


def _section(raw: Mapping[str, Any], name: str, where: str) -> Mapping[str, Any]:
    section = raw.get(name)
    if not isinstance(section, Mapping):
        raise ConfigError(f"{where}[{name}]", "a TOML table")
    return section


def _text(section: Mapping[str, Any], key: str, where: str) -> str:
    value = section.get(key)
    if not isinstance(value, str) or not value:
        raise ConfigError(f"{where}{key}", "a non-empty string", value)
    return value


def _parameter(section: Mapping[str, Any], where: str) -> CalibratedParameter:
    known = {"name", "keys", "unit", "min", "max", "resolution", "source"}
    if unknown := sorted(set(section) - known):
        raise ConfigError(f"{where}{unknown[0]}", "one of " + ", ".join(sorted(known)))
    keys = section.get("keys")
    if not isinstance(keys, list) or not keys or not all(isinstance(k, str) and "." in k for k in keys):
        raise ConfigError(f"{where}keys", "a list of dotted lab-file keys (sensors.LC-03.delay)", keys)
    unit = _text(section, "unit", where)
    low = quantity(f"{where}min", section.get("min"), unit, "nonnegative")
    high = quantity(f"{where}max", section.get("max"), unit, "positive")
    if not high > low:
        raise ConfigError(f"{where}max", f"more than min ({low:g} {unit})", section.get("max"))
    resolution = quantity(f"{where}resolution", section.get("resolution"), unit, "positive")
    return CalibratedParameter(
        _text(section, "name", where),
        tuple(keys),
        unit,
        low,
        high,
        resolution,
        _text(section, "source", where),
    )


def _observation(section: Mapping[str, Any], where: str) -> Observation:
    known = {"kind", "set", "vary", "stable", "unstable"}
    if unknown := sorted(set(section) - known):
        raise ConfigError(f"{where}{unknown[0]}", "one of " + ", ".join(sorted(known)))
    kind_name = _text(section, "kind", where)
    if kind_name not in OBSERVATION_KINDS:
        raise ConfigError(f"{where}kind", " or ".join(OBSERVATION_KINDS), kind_name)
    kind = get_kind(kind_name)
    fixed = section.get("set", {})
    if not isinstance(fixed, Mapping):
        raise ConfigError(f"{where}set", "a table of campaign parameters", fixed)
    if "lab" in fixed:
        raise ConfigError(f"{where}set.lab", "no lab here: the calibration sets the lab")
    settings = convert_settings(kind.params, fixed, where=f"{where}set.")
    vary = _text(section, "vary", where)
    if vary not in kind.params or vary in fixed:
        raise ConfigError(f"{where}vary", f"a parameter of kind {kind_name} not in set", vary)
    stable = kind.params[vary].convert(f"{where}stable", section.get("stable"))
    unstable = kind.params[vary].convert(f"{where}unstable", section.get("unstable"))
    return Observation(kind_name, settings, vary, float(stable), float(unstable))


def lab_with(base: Mapping[str, Any], keys: tuple[str, ...], text: str) -> dict[str, Any]:
    """A copy of the lab data ``base`` with every dotted key of ``keys`` set to ``text``.

    The key's section must exist in ``base`` (``sensors`` for ``sensors.LC-03.delay``);
    tables below it are created (a preset's channel gets its own ``[sensors.LC-03]``).

    Raises
    ------
    ConfigError
        The key's section is not a table of the base lab, or a value stands where a table is needed.
    """
    data = copy.deepcopy(dict(base))
    for key in keys:
        section, *parents, last = key.split(".")
        node: Any = data.get(section)
        if not isinstance(node, dict) or not last:
            raise ConfigError(f"parameter.keys: {key}", "a key under an existing section of the base lab")
        for part in parents:
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise ConfigError(f"parameter.keys: {key}", f"{part} to be a table of the base lab")
        node[last] = text
    return data


def _absolute_files(data: dict[str, Any], base_dir: Path) -> dict[str, Any]:
    """The lab data with ``[table] file`` made absolute (the variant lives in another folder)."""
    table = data.get("table")
    if isinstance(table, dict) and isinstance(table.get("file"), str):
        file = Path(table["file"])
        if not file.is_absolute() and (base_dir / file).exists():
            table["file"] = str((base_dir / file).resolve())
    return data


def _relative_files(data: dict[str, Any], folder: Path) -> dict[str, Any]:
    """The lab data with ``[table] file`` relative to ``folder`` (where the calibrated lab is written)."""
    table = data.get("table")
    if isinstance(table, dict) and isinstance(table.get("file"), str) and Path(table["file"]).is_absolute():
        table["file"] = Path(os.path.relpath(table["file"], folder.resolve())).as_posix()
    return data


class _Runner:
    """Evaluates the observation's setting at a parameter value (runs are cached by value)."""

    def __init__(
        self, protocol: CalibrationProtocol, work: Path, on_run: Callable[[Evaluation], None] | None
    ):
        self.protocol = protocol
        self.work = work
        self.base = _absolute_files(read_toml(protocol.base_lab), protocol.base_lab.parent)
        self.kind = get_kind(protocol.observation.kind)
        self.cache: dict[tuple[float, float], Evaluation] = {}
        self.on_run = on_run

    def value_text(self, value: float) -> str:
        return f"{value:.6g} {self.protocol.parameter.unit}"

    def lab_file(self, value: float, record: Mapping[str, Any] | None = None) -> Path:
        data = lab_with(self.base, self.protocol.parameter.keys, self.value_text(value))
        if record is not None:
            data["calibration"] = dict(record)
        path = self.work / f"lab-{len(self.cache)}.toml"
        path.write_text(toml_text(data), encoding="utf-8")
        return path

    def __call__(self, value: float, setting: float) -> Evaluation:
        key = (value, setting)
        if key in self.cache:
            return self.cache[key]
        obs = self.protocol.observation
        config = copy.deepcopy(dict(self.kind.defaults))
        for name, v in {**obs.settings, obs.vary: setting}.items():
            set_path(config, self.kind.params[name].path, v)
        set_path(config, "lab", str(self.lab_file(value)))
        if self.kind.resolve is not None:
            config = self.kind.resolve(config)
        metrics = self.kind.run(config, self.work / f"run-{len(self.cache)}.h5")
        row = {**metrics, "status": "aborted" if metrics.get("aborted") else "ok"}
        verdict = run_stability(row) or "inconclusive"
        hf = metrics.get("hf_ratio")
        trip = metrics.get("trip_limit")
        result = Evaluation(value, setting, verdict, None if hf is None else float(hf), trip or None)
        self.cache[key] = result
        if self.on_run is not None:
            self.on_run(result)
        return result


def _onset(run: _Runner, setting: float, low: float, high: float, resolution: float) -> float | None:
    """Smallest value in [low, high] where ``setting`` is unstable (bisection; None if stable at high)."""
    if run(high, setting).verdict != "unstable":
        return None
    if run(low, setting).verdict == "unstable":
        return low
    for _ in range(MAX_STEPS):
        if high - low <= resolution:
            break
        mid = 0.5 * (low + high)
        if run(mid, setting).verdict == "unstable":
            high = mid
        else:
            low = mid
    return high


def calibrate(
    protocol: CalibrationProtocol, out_dir: str | Path, on_run: Callable[[Evaluation], None] | None = None
) -> CalibrationResult:
    """Calibrate the protocol's parameter and write the calibrated lab and ``calibration.json`` to ``out_dir``.

    Parameters
    ----------
    protocol : CalibrationProtocol
    out_dir : path
        Folder written whole or not at all: ``calibrated-lab.toml``, ``calibration.json``.
    on_run : callable, optional
        Called with each :class:`Evaluation` (progress).
    """
    par, obs = protocol.parameter, protocol.observation
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ConfigError("--out", "a folder for the calibrated lab (this is a file)", str(out))
    if not out.absolute().parent.is_dir():
        raise ConfigError("--out", "a folder whose parent folder exists", str(out))
    with TemporaryDirectory(prefix="imil-calibrate-") as tmp:
        run = _Runner(protocol, Path(tmp), on_run)
        onset_u = _onset(run, obs.unstable, par.low, par.high, par.resolution)
        if onset_u is None:
            # Not reproduced: keep the end of the range closest to the observation by the claims'
            # own measure, the unstable setting's high-frequency ratio (largest = nearest to unstable).
            ends = {end: run(end, obs.unstable).hf_ratio or 0.0 for end in (par.low, par.high)}
            value, onset_s = max(ends, key=lambda end: ends[end]), None
            note = (
                f"no value of the {par.name} in {run.value_text(par.low)} to {run.value_text(par.high)} "
                f"(the sources' range) makes {obs.vary} = {obs.unstable:g} unstable: the observation is not "
                f"reproduced; kept {run.value_text(value)}, the end where its high-frequency ratio is largest "
                f"({ends[value]:.3g}, against {ends[par.high if value == par.low else par.low]:.3g})"
            )
        else:
            onset_s = _onset(run, obs.stable, onset_u, par.high, par.resolution)
            upper = par.high if onset_s is None else onset_s
            value = 0.5 * (onset_u + upper)
            note = (
                f"{obs.vary} = {obs.unstable:g} is unstable from {run.value_text(onset_u)}; "
                + (
                    f"{obs.vary} = {obs.stable:g} from {run.value_text(onset_s)}"
                    if onset_s is not None
                    else f"{obs.vary} = {obs.stable:g} stays stable up to {run.value_text(par.high)}"
                )
                + f"; calibrated to the midpoint, {run.value_text(value)}"
            )
        at_value = (run(value, obs.stable), run(value, obs.unstable))
        reproduced = at_value[0].verdict == "stable" and at_value[1].verdict == "unstable"
        result = CalibrationResult(
            protocol, value, reproduced, onset_u, onset_s, tuple(run.cache.values()), note
        )
        record = {
            "claim": protocol.claim,
            "parameter": par.name,
            "keys": list(par.keys),
            "value": run.value_text(value),
            "reproduced": reproduced,
            "protocol": protocol.path.name,
        }
        lab_text = toml_text(
            {
                **_relative_files(lab_with(run.base, par.keys, run.value_text(value)), Path(out_dir)),
                "calibration": record,
            },
            f"Calibrated by `imil campaign calibrate {protocol.path.name}` (issue 17, item 2).\n"
            f"Claim calibrated on: {protocol.claim}. {note}.\n"
            "Every other value is the base lab's, from its cited sources.",
        )
        with atomic_directory(out_dir) as folder:
            (folder / "calibrated-lab.toml").write_text(lab_text, encoding="utf-8")
            (folder / "calibration.json").write_text(
                json.dumps(result.to_dict(relative_to=Path(out_dir)), indent=2) + "\n", encoding="utf-8"
            )
    return result
