"""Portable C99 generator of the discrete MIL controller (header + source)."""

from .generator import GeneratedFiles, render_c

__all__ = ["GeneratedFiles", "render_c"]
