"""IEC 61131-3 Structured Text generator in the style of the report's RMC user programs."""

from .generator import render_st

__all__ = ["render_st"]
