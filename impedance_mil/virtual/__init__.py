"""Virtual systems (isolators) the table imitates: SD, LR, FP and user-defined (report Section 5)."""
