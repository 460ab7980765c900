"""A small transpiler that runs one generated ST FUNCTION_BLOCK in Python, in a numpy dtype.

It supports exactly the subset the generators emit: REAL/LREAL scalars and 0-based
arrays, WORD (``16#...`` literals) and BOOL variables, ``:=`` assignments, + - * / with
ST precedence (= Python's), ABS, EXP, EXPT, SQRT, MIN, MAX, SEL, comparisons (``=``,
``<>``), ``AND``/``OR`` between parenthesized operands (bitwise on WORDs, logical on
BOOLs: Python's ``&``/``|`` are both), ``IF ... THEN / ELSIF / ELSE / END_IF`` on lines of
their own, and the generated sign function.  Every REAL value is a numpy scalar of the
dtype, so REAL arithmetic is IEEE single precision; NaN compares as IEEE says.
"""

from __future__ import annotations

import re

import numpy as np

_DECL = re.compile(r"^\s*(\w+) : (?:ARRAY\[0\.\.(\d+)\] OF )?(L?REAL|WORD|BOOL)(?: := ([^;]+))?;", re.M)


def _expression(text: str, prefix: str) -> str:
    text = re.sub(r"(?<![\w.])(\d+\.\d+(?:E-?\d+)?)", r"R(\1)", text)
    text = re.sub(r"16#([0-9A-F]+)", r"0x\1", text)
    text = text.replace("ABS(", "abs(").replace("EXPT(", "POW(").replace(f"{prefix}_sign(", "SIGN(")
    text = text.replace("<>", "!=")
    text = re.sub(r"(?<![<>:!=])=(?!=)", "==", text)
    text = re.sub(r"\bAND\b", "&", text)
    text = re.sub(r"\bOR\b", "|", text)
    return re.sub(r"\bTRUE\b", "True", re.sub(r"\bFALSE\b", "False", text))


def _python(body: str, prefix: str) -> str:
    """The statements of ``body`` as Python, with IF blocks as indented blocks."""
    lines, depth = [], 0
    for raw in body.splitlines():
        line = raw.strip()
        if not line:
            continue
        if line.startswith("IF ") and line.endswith(" THEN"):
            lines.append("    " * depth + f"if {_expression(line[3:-5], prefix)}:")
            depth += 1
            lines.append("    " * depth + "pass")
        elif line.startswith("ELSIF ") and line.endswith(" THEN"):
            lines.append("    " * (depth - 1) + f"elif {_expression(line[6:-5], prefix)}:")
            lines.append("    " * depth + "pass")
        elif line == "ELSE":
            lines.append("    " * (depth - 1) + "else:")
            lines.append("    " * depth + "pass")
        elif line == "END_IF;":
            depth -= 1
        else:
            for stmt in (s.strip() for s in line.split(";")):
                if stmt:
                    lhs, rhs = stmt.split(":=")
                    lines.append("    " * depth + f"{lhs.strip()} = {_expression(rhs.strip(), prefix)}")
    if depth:
        raise ValueError("unbalanced IF/END_IF")
    return "\n".join(lines)


class STBlock:
    """Transpile one generated FUNCTION_BLOCK to Python and run it, one call per scan."""

    def __init__(self, text: str, block: str, prefix: str, dtype):
        src = re.search(rf"FUNCTION_BLOCK {block}\n(.*?)END_FUNCTION_BLOCK", text, re.S).group(1)
        src = re.sub(r"\(\*.*?\*\)", "", src, flags=re.S)
        self.env = {
            "R": dtype,
            "POW": np.power,
            "EXP": np.exp,
            "abs": abs,
            "SIGN": lambda v: dtype(np.sign(v)),
            "SEL": lambda g, in0, in1: in1 if g else in0,
            "MIN": min,
            "MAX": max,
            "SQRT": np.sqrt,
        }
        self.dtype = dtype
        for name, n, kind, init in _DECL.findall(src):
            if kind == "WORD":
                self.env[name] = int(_expression(init or "16#0", prefix), 16)
            elif kind == "BOOL":
                self.env[name] = init == "TRUE"
            else:
                self.env[name] = np.zeros(int(n) + 1, dtype) if n else dtype(float(init or 0.0))
        body = src[src.rindex("END_VAR") + len("END_VAR") :]
        self.code = compile(_python(body, prefix), block, "exec")

    def __call__(self, **inputs):
        for k, v in inputs.items():
            self.env[k] = v if isinstance(v, bool) else self.dtype(v)
        with np.errstate(all="ignore"):  # NaN and overflow are what the guard tests feed
            exec(self.code, self.env)  # noqa: S102 - our own generated, transpiled code
        return self.env
