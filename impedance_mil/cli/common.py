"""Small helpers shared by the CLI commands (printing, JSON output)."""

from __future__ import annotations

import json
import math
from typing import Any

from rich.console import Console

#: Console for human-readable output (stdout).
console = Console(highlight=False, soft_wrap=True)


def _clean(value: Any) -> Any:
    """Make values JSON-safe: NaN/inf become null, numpy scalars become floats."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if hasattr(value, "tolist"):
        return _clean(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def print_json(data: Any) -> None:
    """Print ``data`` as JSON on stdout (NaN and inf become null)."""
    print(json.dumps(_clean(data), indent=2))
