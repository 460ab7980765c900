"""Virtual lab: the sampled-data loop, experiments, safety limits, metrics (report Sections 4.5, 8, 9)."""
