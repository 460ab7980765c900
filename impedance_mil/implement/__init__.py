"""Implementation: discretization, runtime controller, code generators (report Sections 6.5, 7)."""
