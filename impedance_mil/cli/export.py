"""`imil export` command (placeholder until the implementation issue lands)."""

from __future__ import annotations


def export() -> None:
    """Export a design as C, IEC 61131-3 ST, JSON or CSV (not yet available)."""
    print("imil export: not yet available")
