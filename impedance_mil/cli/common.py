"""Small helpers shared by the CLI commands (printing, JSON output)."""

from __future__ import annotations

import json
from typing import Any

from rich.console import Console

from ..fileio import json_safe

#: Console for human-readable output (stdout).
console = Console(highlight=False, soft_wrap=True)


def print_json(data: Any) -> None:
    """Print ``data`` as JSON on stdout (NaN and inf become null)."""
    print(json.dumps(json_safe(data), indent=2))
