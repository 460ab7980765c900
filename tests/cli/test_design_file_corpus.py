"""Bad-input corpus of design files through ``imil export`` (issue 18, findings 2, 3 and 7).

Every field of a valid design file (top level, filter, table, VS entry, first
constraint and the transfer functions' coefficients) is replaced in turn by
each of :data:`WRONG_VALUES`, and raw texts no JSON reader should choke on
(nesting 3000 deep, a 400-digit or 2-million-digit number, NaN, truncation)
are added.  Each run, in-process, must either be refused -- exit status 2, one
line on stderr naming the file and the field, no traceback, nothing written --
or, for the few replacements that are valid values of their field
(:data:`VALID`), export normally.  The counts are printed for the issue's note.
"""

from __future__ import annotations

import copy
import json

import pytest

#: Replacements tried for every field: wrong types, degenerate and hostile numbers.
WRONG_VALUES = {
    "null": None,
    "true": True,
    "string": "x",
    "empty list": [],
    "object": {"a": 1},
    "negative": -1.0,
    "zero": 0,
    "1e308": 1e308,
    "400 digits": 10**400,
    "nested": [[[[[[[[[[1]]]]]]]]]],
}

#: Constraint fields by the values they may take (the others are verdicts, true or false).
_SIGNED = ("magnitude_error_db", "phase_error_deg", "passivity_margin_deg", "passivity_tolerant_margin_deg")
# The passivity indices (issue 15): signed (a non-passive design has a negative index), null when
# not evaluated.
_SIGNED += ("passivity_margin_sampled_deg", "passivity_index")
_NONNEGATIVE = ("performance_error", "effort_ratio", "performance_worst_hz", "effort_worst_hz")
_NONNEGATIVE += ("passivity_worst_hz", "passivity_tolerant_worst_hz")

#: (field, replacement) pairs that are valid values of the field, exported normally: an
#: absent f_h path, feasible band or VS (exported without a MIL step, with a note), no
#: warnings or evaluated constraints, any version string and VS label, a filter order 0
#: (a path proper without filtering), in-range table values (zero pressure feedback,
#: return pressure or oil damping), other leading coefficients, and the constraint
#: results' own values (null is "not evaluated").
VALID = {
    ("H_ufh", "null"),
    ("feasible_fc_hz", "null"),
    ("warnings", "empty list"),
    ("constraints", "empty list"),
    ("vs", "null"),
    ("software_version", "string"),
    ("vs.name", "null"),
    ("vs.name", "string"),
    ("filter.order_z", "zero"),
    ("filter.order_w", "zero"),
    ("filter.order_fh", "zero"),
    ("filter.ripple_db", "zero"),
    ("filter.fc_w_hz", "null"),
    ("filter.fc_w_hz", "1e308"),  # a record of the design (continuous); H_uw is what is exported
    ("table.Kp", "zero"),
    ("table.zeta_oil", "zero"),
    ("table.return_pressure", "zero"),
    ("table.loop_time", "zero"),
    *((f"{h}.num[0]", v) for h in ("H_uz", "H_uw") for v in ("negative", "zero")),
    *((f"constraints[0].{k}", v) for k in _SIGNED for v in ("null", "negative", "zero", "1e308")),
    *((f"constraints[0].{k}", v) for k in _NONNEGATIVE for v in ("null", "zero", "1e308")),
    *((f"constraints[0].{k}", "true") for k in ("I", "II", "III", "stable")),
    # The verdicts of III per model (issue 15, item 2): true or false, null when not evaluated.
    *((f"constraints[0].{k}", v) for k in ("III_design_model", "III_sampled") for v in ("null", "true")),
    ("constraints[0].fc_hz", "1e308"),
}


@pytest.fixture
def document(sd2_design_document):
    return sd2_design_document


def _fields(doc) -> list[tuple[str, tuple]]:
    """(name, path) of every field replaced: top level, and one level into the objects."""
    out = []
    for key, value in doc.items():
        out.append((key, (key,)))
        if key in ("filter", "table") or (key == "vs" and value):
            out += [(f"{key}.{k}", (key, k)) for k in value if not (key == "vs" and k == "parameters")]
        if key == "vs" and value:
            out += [(f"vs.parameters.{k}", ("vs", "parameters", k)) for k in value["parameters"]]
    out += [(f"constraints[0].{k}", ("constraints", 0, k)) for k in doc["constraints"][0]]
    out += [(f"{k}.{p}[0]", (k, p, 0)) for k in ("H_uz", "H_uw") for p in ("num", "den")]
    return out


def _replaced(doc, path, value):
    doc = copy.deepcopy(doc)
    target = doc
    for step in path[:-1]:
        target = target[step]
    target[path[-1]] = value
    return doc


def _cases(doc):
    for name, path in _fields(doc):
        for label, value in WRONG_VALUES.items():
            yield name, label, json.dumps(_replaced(doc, path, value), indent=2)


def _names(doc, name, label, text) -> list[str]:
    """What a refusal of ``name`` may name: the field, its object (``H_uz`` for a coefficient),
    a field of the same object (a derived VS value its parameters give), the whole file, or
    the line of a number refused before parsing (it has no key yet)."""
    if name == "(whole file)":
        return ["bad.json"]
    if label == "400 digits":
        return [f"line {text[: text.index('1' + '0' * 399)].count(chr(10)) + 1}:"]
    parts = name.replace("[0]", "").split(".")
    names = [parts[-1], parts[0]]
    if name.startswith("vs.parameters."):
        names += [f"parameters.{k}" for k in doc["vs"]["parameters"]]
    return names


RAW_TEXTS = {
    "3000 levels deep": "[" * 3000 + "]" * 3000,
    "2 million digits": '{"format": ' + "7" * 2_000_000 + "}",
    "NaN": '{"format": "impedance-mil/design", "version": NaN}',
    "not JSON": "{format: design}",
    "empty": "",
    "a JSON number": "3",
    "binary": "\x00\xff\x00",
}


def test_corpus_of_design_files_through_export(imil, tmp_path, document):
    counts = {"refused": 0, "exported (valid value)": 0}
    problems = []
    cases = list(_cases(document))
    cases += [("(whole file)", label, text) for label, text in RAW_TEXTS.items()]
    cases.append(
        ("sign_convention", "other", json.dumps({**document, "sign_convention": "u = H_uz*z_vs - H_uw*w"}))
    )
    cases.append(("version", "true", json.dumps({**document, "version": True})))
    for i, (name, label, text) in enumerate(cases):
        case = tmp_path / f"case{i}"
        case.mkdir()
        (case / "bad.json").write_text(text, encoding="utf-8", errors="surrogateescape")
        r = imil("export", "bad.json", "--format", "c", "-o", "out", cwd=case)
        if (name, label) in VALID:
            if r.returncode != 0:
                problems.append(f"{name} = {label}: a valid value was refused: {r.stderr.strip()}")
            counts["exported (valid value)"] += 1
            continue
        lines = r.stderr.strip().splitlines()
        if r.returncode != 2 or len(lines) != 1 or "Traceback" in r.stderr:
            problems.append(f"{name} = {label}: exit {r.returncode}, stderr {r.stderr.strip()[:300]!r}")
        elif "bad.json" not in lines[0] or not any(
            n in lines[0] for n in _names(document, name, label, text)
        ):
            problems.append(f"{name} = {label}: does not name the file and the field: {lines[0]}")
        elif sorted(p.name for p in case.iterdir()) != ["bad.json"]:
            problems.append(f"{name} = {label}: wrote {sorted(p.name for p in case.iterdir())}")
        else:
            counts["refused"] += 1
    print(f"design-file corpus: {len(cases)} cases, {counts}, {len(problems)} problems")
    assert not problems, "\n".join(problems) + f"\n({len(problems)} in all)"
    assert len(cases) > 400
