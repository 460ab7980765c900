"""`imil demo`: the main job on the built-in default (placeholder)."""

from __future__ import annotations

from pathlib import Path

import typer


def demo(out: Path = typer.Option(Path("demo-output"), "--out", help="Output folder.")) -> None:
    """Run the main job on the report's default configuration."""
    out.mkdir(parents=True, exist_ok=True)
    print(f"imil demo: nothing to run yet; output folder {out}")
