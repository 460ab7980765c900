"""MIL controller design: controller forms, filters, constraints I/II/III (report Section 6, 9.4)."""
