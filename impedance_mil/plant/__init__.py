"""Characterize the shake table: linear model, tuning, valve fit (report Section 4)."""
