"""Campaign files: read, validate and expand into a list of runs.

A campaign file is TOML::

    [campaign]
    name = "sd-sweep"
    kind = "mil"                 # a kind of impedance_mil.campaign.kinds.KINDS
    title = "SD systems, three motions"
    section = "9.3"              # report section it reproduces (optional)
    base_config = "lab.toml"     # optional: a run configuration merged over the kind's defaults

    [base]                       # parameter settings shared by every run
    K_p = "0.001 V/psi"

    [reduced.base]               # with --reduced: extra base settings (e.g. shorter records)
    duration = "8 s"

    [[study]]                    # the campaign is the union of its studies
    name = "table-9.4"
    kind = "mil"                 # optional: a study may use another kind than the campaign's
    set = { f_c = "80 Hz" }      # settings fixed for this study
    product = { vs = ["SD1", "SD2"], motion = ["GM1", "GM2", "GM3"] }   # Cartesian product
    zip = { m_vs_ratio = [1.25, 1.0], f_c = [80, 200] }                # lists varied together
    cases = [ { feedback = "none" }, { feedback = "load_cells" } ]       # explicit list
    reduced = { motion = ["GM1"] }   # replacement lists with --reduced (or false: drop the study)

Runs of a study = ``cases x product x zip`` (each optional).  A run's settings
are ``base``, then the study's ``set``, then its own values; a parameter may
appear only once among ``set``, ``cases``, ``product`` and ``zip``.  Every
value is validated against the kind's parameters (name, unit, range) before
anything runs, and the number of runs is checked against ``max_runs`` before
the list is built.  The campaign's name is one safe path component (it names
the default folder ``campaign-NAME``, which must stay where it is asked to
be), and no two studies share a name (their runs would be merged).
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..config import read_toml
from ..errors import ConfigError, DataFileError
from .kinds import Kind, get_kind
from .params import convert_settings, deep_merge, set_path
from .store import run_id_for

#: Default largest number of runs a campaign may expand to (``--max-runs``).
DEFAULT_MAX_RUNS = 10_000

#: Folder of the built-in campaign files.
BUILTIN_DIR = Path(__file__).resolve().parent.parent / "data" / "campaigns"

#: A campaign name: it names the default folder (``campaign-NAME``), so one safe path component.
NAME_PATTERN = r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}"
_NAME_RE = re.compile(NAME_PATTERN)

_TOP_KEYS = {"campaign", "base", "study", "reduced"}
_CAMPAIGN_KEYS = {"name", "kind", "title", "section", "base_config", "description"}
_STUDY_KEYS = {"name", "kind", "set", "product", "zip", "cases", "reduced", "title"}


@dataclass(frozen=True)
class RunSpec:
    """One run of a campaign.

    Attributes
    ----------
    run_id : str
        Short sha256 prefix of the canonical JSON of ``{"kind", "config"}``.
    kind : str
        The campaign kind of the run (the study's, else the campaign's).
    studies : tuple of str
        The studies that asked for this run (one run may serve several).
    settings : dict
        Parameter name -> value in internal units (base, study and own values).
    config : dict
        The full run configuration handed to the run function.
    """

    run_id: str
    kind: str
    studies: tuple[str, ...]
    settings: dict[str, Any]
    config: dict[str, Any]


@dataclass(frozen=True)
class CampaignSpec:
    """A validated, expanded campaign.

    Attributes
    ----------
    name, kind, title, section : str
        From the ``[campaign]`` table (``kind`` is the default kind of its studies).
    source : str
        The file it was read from.
    reduced : bool
        Whether the reduced (CI) version was expanded.
    runs : tuple of RunSpec
        Every distinct run, in file order.
    parameters : tuple of str
        Parameter names set in any run (summary-table columns), in first-use order.
    """

    name: str
    kind: str
    title: str
    section: str
    source: str
    reduced: bool
    runs: tuple[RunSpec, ...]
    parameters: tuple[str, ...]


def builtin_campaigns() -> dict[str, Path]:
    """The built-in campaign files, by name (file stem)."""
    if not BUILTIN_DIR.is_dir():
        return {}
    return {p.stem: p for p in sorted(BUILTIN_DIR.glob("*.toml"))}


def resolve_campaign(ref: str | Path) -> Path:
    """Find a campaign file: an existing path, else a built-in campaign name.

    Raises
    ------
    DataFileError
        Neither a file nor a built-in name.
    """
    path = Path(ref)
    if path.is_file():
        return path
    builtins = builtin_campaigns()
    if str(ref) in builtins:
        return builtins[str(ref)]
    raise DataFileError(
        ref, "no such campaign file or built-in campaign (built-ins: " + ", ".join(builtins) + ")"
    )


def load_campaign(
    ref: str | Path,
    *,
    reduced: bool = False,
    max_runs: int = DEFAULT_MAX_RUNS,
    overrides: Mapping[str, Any] | None = None,
) -> CampaignSpec:
    """Read, validate and expand a campaign file or built-in campaign.

    Parameters
    ----------
    ref : str or Path
        A campaign file, or the name of a built-in campaign (e.g. ``"report-sec9"``).
    reduced : bool
        Expand the reduced (CI) version: apply ``[reduced]`` and each study's ``reduced``.
    max_runs : int
        Refuse campaigns that expand to more runs than this.
    overrides : mapping, optional
        Extra base settings (``imil campaign run --set KEY=VALUE``), applied last.

    Returns
    -------
    CampaignSpec

    Raises
    ------
    ConfigError
        Unknown keys or parameters, empty lists, wrong dimensions, too many runs.
    DataFileError
        The file (or its ``base_config``) is missing or not TOML.
    """
    path = resolve_campaign(ref)
    raw = read_toml(path)
    _check_keys(raw, _TOP_KEYS, "")
    head = raw.get("campaign")
    if not isinstance(head, dict):
        raise ConfigError("campaign", "a [campaign] table with name and kind")
    _check_keys(head, _CAMPAIGN_KEYS, "campaign.")
    kind = get_kind(_text(head, "kind", "campaign."))
    name = _name(_text(head, "name", "campaign.", default=path.stem), "campaign.name")
    base_file = _base_config(head, path)
    reduced_table = _table(raw, "reduced", "")
    _check_keys(reduced_table, {"base"}, "reduced.")
    base_raw = {**_table(raw, "base", "")}
    if reduced:
        base_raw.update(_table(reduced_table, "base", "reduced."))
    base_raw.update(overrides or {})
    studies = _studies(raw, reduced)
    total = sum(_count(study, where) for where, study in studies)
    if total > max_runs:
        raise ConfigError("--max-runs", f"at most {max_runs} runs", f"{total} runs in {path}")
    kinds = [get_kind(_text(study, "kind", where + ".", default=kind.name)) for where, study in studies]
    known = set().union(*(k.params for k in kinds))
    for key in base_raw:
        if key not in known:
            raise ConfigError(f"base.{key}", "a known parameter (" + ", ".join(sorted(known)) + ")")
    runs: dict[str, RunSpec] = {}
    columns: dict[str, None] = {}
    for (where, study), study_kind in zip(studies, kinds):
        base = _base_settings(study_kind, base_raw)
        defaults = deep_merge(study_kind.defaults, base_file)
        columns.update(dict.fromkeys(base))
        for settings in _expand(study_kind, study, where):
            columns.update(dict.fromkeys(settings))
            _add_run(runs, study_kind, defaults, {**base, **settings}, str(study.get("name", where)))
    return CampaignSpec(
        name=name,
        kind=kind.name,
        title=str(head.get("title", name)),
        section=str(head.get("section", "")),
        source=str(path),
        reduced=reduced,
        runs=tuple(runs.values()),
        parameters=tuple(columns),
    )


def _base_settings(kind: Kind, base_raw: Mapping[str, Any]) -> dict[str, Any]:
    """The base settings a study's kind accepts (other kinds of the campaign may use the rest)."""
    known = {k: v for k, v in base_raw.items() if k in kind.params}
    return convert_settings(kind.params, known, where="base.")


def _add_run(
    runs: dict[str, RunSpec], kind: Kind, defaults: Mapping[str, Any], settings: dict[str, Any], study: str
) -> None:
    config = deep_merge(defaults, {})
    for key, value in settings.items():
        set_path(config, kind.params[key].path, value)
    if kind.resolve is not None:
        config = kind.resolve(config)
    run_id = run_id_for(kind.name, config)
    if run_id in runs:
        old = runs[run_id]
        if study not in old.studies:
            runs[run_id] = RunSpec(run_id, kind.name, old.studies + (study,), old.settings, old.config)
        return
    runs[run_id] = RunSpec(run_id, kind.name, (study,), settings, config)


def _studies(raw: Mapping[str, Any], reduced: bool) -> list[tuple[str, dict[str, Any]]]:
    items = raw.get("study", [])
    if isinstance(items, dict):
        items = [items]
    if not isinstance(items, list) or not items:
        raise ConfigError("study", "at least one [[study]] table")
    out = []
    names: set[str] = set()
    for index, study in enumerate(items):
        where = f"study[{index}]"
        if not isinstance(study, dict):
            raise ConfigError(where, "a table", study)
        if "name" in study:
            _text(study, "name", where + ".")
            if study["name"] in names:
                raise ConfigError(
                    f"{where}.name", "a name no other study has (two studies would be merged)", study["name"]
                )
            names.add(study["name"])
        where = f"study.{study.get('name', index)}"
        _check_keys(study, _STUDY_KEYS, where + ".")
        rule = study.get("reduced", True)
        if reduced and rule is False:
            continue
        if reduced and isinstance(rule, dict):
            study = {**study, "product": {**study.get("product", {}), **rule}}
        elif not isinstance(rule, (bool, dict)):
            raise ConfigError(where + ".reduced", "a table of replacement lists, or false", rule)
        out.append((where, study))
    if not out:
        raise ConfigError("study", "at least one study left in the reduced campaign")
    return out


def _count(study: Mapping[str, Any], where: str) -> int:
    """Number of runs a study expands to, checked before expansion."""
    n = 1
    for key, values in _table(study, "product", where + ".").items():
        _check_list(values, f"{where}.product.{key}")
        n *= len(values)
    zipped = _table(study, "zip", where + ".")
    lengths = set()
    for key, values in zipped.items():
        _check_list(values, f"{where}.zip.{key}")
        lengths.add(len(values))
    if len(lengths) > 1:
        raise ConfigError(f"{where}.zip", "lists of equal length", sorted(lengths))
    n *= lengths.pop() if lengths else 1
    cases = study.get("cases", [{}])
    _check_list(cases, f"{where}.cases")
    if not all(isinstance(case, dict) for case in cases):
        raise ConfigError(f"{where}.cases", "a list of tables", cases)
    return n * len(cases)


def _expand(kind: Kind, study: Mapping[str, Any], where: str) -> list[dict[str, Any]]:
    fixed = convert_settings(kind.params, _table(study, "set", where + "."), where=where + ".set.")
    product = {
        key: [_kind_value(kind, f"{where}.product.{key}", v) for v in values]
        for key, values in _table(study, "product", where + ".").items()
    }
    zipped = {
        key: [_kind_value(kind, f"{where}.zip.{key}", v) for v in values]
        for key, values in _table(study, "zip", where + ".").items()
    }
    cases = [
        convert_settings(kind.params, case, where=f"{where}.cases[{i}].")
        for i, case in enumerate(study.get("cases", [{}]))
    ]
    _check_disjoint(where, fixed, product, zipped, cases)
    zip_rows = [dict(zip(zipped, row)) for row in zip(*zipped.values())] or [{}]
    out = []
    for case in cases:
        for combo in itertools.product(*product.values()):
            for row in zip_rows:
                out.append({**fixed, **case, **dict(zip(product, combo)), **row})
    return out


def _kind_value(kind: Kind, key: str, raw: Any) -> Any:
    """Validate one value of a varied parameter (``key`` ends with the parameter name)."""
    name = key.rsplit(".", 1)[-1]
    if name not in kind.params:
        raise ConfigError(key, "a known parameter (" + ", ".join(sorted(kind.params)) + ")")
    return kind.params[name].convert(key, raw)


def _check_disjoint(where: str, *groups: Any) -> None:
    seen: set[str] = set()
    for group in groups:
        keys = set().union(*group) if isinstance(group, list) else set(group)
        clash = seen & keys
        if clash:
            raise ConfigError(
                f"{where}.{sorted(clash)[0]}", "each parameter in only one of set, cases, product, zip"
            )
        seen |= keys


def _check_list(values: Any, key: str) -> None:
    if not isinstance(values, list):
        raise ConfigError(key, "a list of values", values)
    if not values:
        raise ConfigError(key, "a non-empty list (an empty list would give no runs)", values)


def _check_keys(table: Mapping[str, Any], known: set[str], where: str) -> None:
    unknown = sorted(set(table) - known)
    if unknown:
        raise ConfigError(f"{where}{unknown[0]}", "one of the keys " + ", ".join(sorted(known)))


def _table(parent: Mapping[str, Any], key: str, where: str) -> dict[str, Any]:
    value = parent.get(key, {})
    if not isinstance(value, dict):
        raise ConfigError(f"{where}{key}", "a table", value)
    return value


def _text(table: Mapping[str, Any], key: str, where: str, default: str | None = None) -> str:
    value = table.get(key, default)
    if not isinstance(value, str) or not value:
        raise ConfigError(f"{where}{key}", "a non-empty string", value)
    return value


def _name(value: str, key: str) -> str:
    """A campaign name that is one safe path component (no ``/``, no ``..``, no leading dot)."""
    if not _NAME_RE.fullmatch(value):
        raise ConfigError(
            key,
            "a name of at most 64 letters, digits, '.', '_' or '-', starting with a letter or digit",
            value,
        )
    return value


def _base_config(head: Mapping[str, Any], path: Path) -> dict[str, Any]:
    ref = head.get("base_config")
    if ref is None:
        return {}
    if not isinstance(ref, str):
        raise ConfigError("campaign.base_config", "a path to a TOML run configuration", ref)
    base_path = Path(ref) if Path(ref).is_absolute() else path.parent / ref
    return read_toml(base_path)
