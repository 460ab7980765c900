"""`imil design` command (placeholder until the design issue lands)."""

from __future__ import annotations


def design() -> None:
    """Design the impedance-matching MIL controller (not yet available)."""
    print("imil design: not yet available")
