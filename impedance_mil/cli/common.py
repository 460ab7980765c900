"""Small helpers shared by the CLI commands (printing, JSON output, the table option)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, List, Optional

from rich.console import Console

from ..config import parse_overrides
from ..fileio import json_safe
from ..plant import TableParameters, default_table_path

#: Console for human-readable output (stdout).
console = Console(highlight=False, soft_wrap=True)


def print_json(data: Any) -> None:
    """Print ``data`` as JSON on stdout (NaN and inf become null)."""
    print(json.dumps(json_safe(data), indent=2))


def table_parameters(table: Optional[Path], sets: Optional[List[str]] = None) -> TableParameters:
    """``--table`` (default report Table 4.1) with ``--set`` overrides (errors name the key or file)."""
    return TableParameters.from_toml(table or default_table_path(), parse_overrides(sets))
