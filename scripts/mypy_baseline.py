"""Run mypy on the library and compare its errors with the committed baseline.

The baseline (``mypy-baseline.txt``) lists the errors mypy reported when type
checking was introduced, one per line as ``file: [code] message`` (no line
numbers, so that unrelated edits do not invalidate it).  It may only shrink:

- an error that is not in the baseline fails the check (fix it);
- a baseline entry that mypy no longer reports also fails the check, so that
  each fix is committed with the shorter baseline (``--update`` rewrites it).

Usage: ``python scripts/mypy_baseline.py [--update]`` (exit 0 when they agree).
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BASELINE = ROOT / "mypy-baseline.txt"
_LINE = re.compile(r"^(?P<file>[^:]+):\d+(?::\d+)?: error: (?P<msg>.*?)\s+\[(?P<code>[a-z-]+)\]$")


def current_errors() -> Counter[str]:
    """mypy's errors on the library, normalised (no line numbers)."""
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", "--no-error-summary"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    if proc.returncode not in (0, 1):
        sys.exit(f"mypy failed to run:\n{proc.stdout}{proc.stderr}")
    errors: Counter[str] = Counter()
    for line in proc.stdout.splitlines():
        m = _LINE.match(line)
        if m:
            errors[f"{m['file']}: [{m['code']}] {m['msg']}"] += 1
    return errors


def main(argv: list[str]) -> int:
    errors = current_errors()
    if "--update" in argv:
        BASELINE.write_text("".join(f"{e}\n" for e in sorted(errors.elements())))
        print(f"mypy baseline: {sum(errors.values())} entries written to {BASELINE.name}")
        return 0
    baseline: Counter[str] = (
        Counter(line for line in BASELINE.read_text().splitlines() if line.strip())
        if BASELINE.exists()
        else Counter()
    )
    new, fixed = errors - baseline, baseline - errors
    for e in sorted(new.elements()):
        print(f"new mypy error: {e}")
    for e in sorted(fixed.elements()):
        print(f"fixed (remove from {BASELINE.name}, or run with --update): {e}")
    print(f"mypy: {sum(errors.values())} errors, baseline {sum(baseline.values())}")
    return 1 if new or fixed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
