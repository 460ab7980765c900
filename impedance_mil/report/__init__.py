"""Figures and HTML reports (the only package that imports matplotlib)."""
