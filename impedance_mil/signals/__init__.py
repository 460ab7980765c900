"""Ground motions, response spectra, multisines and FRF estimation (report Sections 4.5, 8.2)."""
